// SPDX-License-Identifier: MIT
// Encoding a relightable picture as a Relight web RTI (bilinear grid, mrgb PCA planes).
#include "vpe/relight_web/relight_web_encoder.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <mutex>
#include <unordered_map>
#include <utility>

#include <Eigen/Dense>
#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/image/image_file.h"
#include "vpe/relight_web/bilinear_light_grid.h"
#include "vpe/relight_web/floored_projection.h"

namespace vpe::relight_web {

namespace {

// Pixels the covariance is estimated from: enough for a stable basis of a few hundred
// dimensions, few enough that a large picture does not cost minutes.
constexpr std::size_t kCovarianceSamples = 262144;

// OpenLIME raises every decoded value to the power 2.2 unclamped, and pow() of a negative
// number is undefined in GLSL (coloured specks). The encoder keeps every value decoded at a
// grid node at least kFloor, or the mean's own value where that is lower; between nodes a
// light blends four of them with non-negative weights. Both are far below anything OpenLIME
// shows: its 8-bit linear buffer stores every value under 0.059 (15/255) as 0.
constexpr double kFloor = 1.0 / 255.0;
// Grid values below a node's black level are encoded as that level: kBlack, or more where a
// trial encoding decodes that node's black pixels further down (PCA, rounding and JPEG
// together: kFloor plus the 99.9th percentile of their drop), up to kBlackCap. Nine PCA
// planes cannot hold a value of exactly 0 without error, nor can JPEG planes at quality 95
// (a few 255ths at a node): at 0 about half of the black pixels decode below it, and holding
// them all at the floor costs the other nodes. As OpenLIME shows it (held-out lights, R 8,
// K 9): item1's paper model 40.74 dB before the floor, 40.43 with black at 4/255, 40.87 with
// these levels; its extended model 39.22 and 39.33 dB (all 60 lights: 38.81 before). The
// levels stay below 15/255, all of which OpenLIME shows as black.
constexpr double kBlack = 4.0 / 255.0;
constexpr double kBlackCap = 12.0 / 255.0;
// The mean's smallest byte, so that every node leaves room for kFloor and for the planes'
// rounding.
constexpr int kMeanFloorByte = 2;
// Rounds of writing the planes, decoding them and raising the floor of the pixels whose
// rounding and JPEG compression took a node below kFloor / 2.
constexpr int kRepairRounds = 16;
// What a pixel's floor rises by beyond its shortfall, times the rounds it came back in.
constexpr double kRepairMargin = 2.0 / 255.0;

void validate(int width, int height, const RelightWebOptions& options) {
    if (width <= 0 || height <= 0) {
        throw common::InputError("relight export: the picture is empty");
    }
    if (options.resolution < BilinearLightGrid::kMinResolution ||
        options.resolution > BilinearLightGrid::kMaxResolution) {
        throw common::InputError("--resolution " + std::to_string(options.resolution) +
                                 " is outside " +
                                 std::to_string(BilinearLightGrid::kMinResolution) + ".." +
                                 std::to_string(BilinearLightGrid::kMaxResolution));
    }
    const int dimensions = options.resolution * options.resolution * 3;
    // OpenLIME's mrgb shader reads three planes from every JPEG and indexes its uniform arrays
    // by them, so a count that is not a multiple of 3 would read past the arrays.
    if (options.planes < 3 || options.planes % 3 != 0 || options.planes > dimensions) {
        throw common::InputError("--planes " + std::to_string(options.planes) +
                                 " must be a multiple of 3 between 3 and " +
                                 std::to_string(dimensions) + " (3 · resolution²)");
    }
    if (options.quality < 1 || options.quality > 100) {
        throw common::InputError("--quality " + std::to_string(options.quality) +
                                 " is outside 1..100");
    }
}

std::uint8_t toByte(double value) {
    return static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
}

void writeJpeg(const std::filesystem::path& path, int width, int height,
               const std::vector<std::uint8_t>& pixels, int quality) {
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("Compression", "jpeg:" + std::to_string(quality));
    // The three channels are unrelated coefficients: chroma subsampling would blur two of
    // them (Relight writes its planes without it too).
    spec.attribute("jpeg:subsampling", "4:4:4");
    if (!out || !out->open(path.string(), spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close()) {
        throw common::InputError(
            path, "cannot write plane: " + (out ? out->geterror() : OIIO::geterror()));
    }
}

// Grid values: one column per pixel, its colour at every grid node (node-major, then RGB),
// the vector OpenLIME's basis is laid out in. kNodes: the subject under each node's light;
// kLeastSquares: the node values whose bilinear interpolation best matches the subject under
// the lights of a twice-as-fine grid.
Eigen::MatrixXf renderGridValues(const BilinearLightGrid& grid, Eigen::Index pixels,
                                 const LightRenderer& render, const RelightWebOptions& options) {
    const int nodes = grid.nodeCount();
    const Eigen::Index dimensions = nodes * 3;
    Eigen::MatrixXf samples = Eigen::MatrixXf::Zero(dimensions, pixels);
    std::vector<float> rgb;
    // samples += (perNode ⊗ I₃) · image: one matrix product rather than strided row updates.
    const auto addRendering = [&](const proto::Vec3d& light, const Eigen::VectorXd& perNode) {
        rgb.assign(static_cast<std::size_t>(pixels) * 3, 0.0f);
        render(light, rgb);
        const Eigen::Map<const Eigen::MatrixXf> image(rgb.data(), 3, pixels);
        Eigen::MatrixXf spread = Eigen::MatrixXf::Zero(dimensions, 3);
        for (int node = 0; node < nodes; ++node) {
            for (int c = 0; c < 3; ++c) {
                spread(node * 3 + c, c) = static_cast<float>(perNode(node));
            }
        }
        samples.noalias() += spread * image;
    };
    if (options.grid == GridValues::kNodes) {
        for (int node = 0; node < nodes; ++node) {
            addRendering(grid.nodeDirection(node), Eigen::VectorXd::Unit(nodes, node));
        }
        return samples;
    }
    // What a viewer sees between the nodes counts, not only at them (Relight fits its nodes to
    // the capture's lights the same way), in the least-squares sense: V = (WᵀW + λI)⁻¹WᵀF over
    // the fine grid's nodes and every midpoint between them.
    const BilinearLightGrid fine(2 * options.resolution - 1);
    Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(fine.nodeCount(), nodes);
    for (int j = 0; j < fine.nodeCount(); ++j) {
        const LightGridWeights w = grid.weights(fine.nodeDirection(j));
        for (std::size_t k = 0; k < 4; ++k) {
            weights(j, w.nodes[k]) += w.weights[k];
        }
    }
    // A light ridge keeps the system well posed without pulling the fit (weights ≤ 1).
    constexpr double kRidge = 1e-4;
    const Eigen::MatrixXd normal =
        weights.transpose() * weights + kRidge * Eigen::MatrixXd::Identity(nodes, nodes);
    const Eigen::MatrixXd solve = normal.ldlt().solve(weights.transpose());
    for (int j = 0; j < fine.nodeCount(); ++j) {
        addRendering(fine.nodeDirection(j), solve.col(j));
    }
    return samples;
}

// The principal components of the grid values: their mean, the `planes` leading directions
// and the share of the variance those keep.
struct PrincipalPlanes {
    Eigen::VectorXd mean;
    Eigen::MatrixXd eigenvectors;  // a column per plane, the largest first
    double retainedVariance = 0;
};

// Mean and covariance (in double: sums over many pixels), on an even subsample.
PrincipalPlanes principalPlanes(const Eigen::MatrixXf& samples, int planes) {
    const Eigen::Index dimensions = samples.rows();
    const Eigen::Index pixels = samples.cols();
    PrincipalPlanes pca;
    pca.mean = samples.cast<double>().rowwise().mean();
    const Eigen::Index stride =
        std::max<Eigen::Index>(1, pixels / static_cast<Eigen::Index>(kCovarianceSamples));
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(dimensions, dimensions);
    constexpr Eigen::Index kBlock = 4096;
    Eigen::MatrixXd block(dimensions, kBlock);
    Eigen::Index filled = 0;
    Eigen::Index used = 0;
    for (Eigen::Index p = 0; p < pixels; p += stride) {
        block.col(filled++) = samples.col(p).cast<double>() - pca.mean;
        ++used;
        if (filled == kBlock) {
            covariance.noalias() += block * block.transpose();
            filled = 0;
        }
    }
    if (filled > 0) {
        covariance.noalias() += block.leftCols(filled) * block.leftCols(filled).transpose();
    }
    covariance /= static_cast<double>(used);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
    // Eigenvalues ascend: the principal directions are the last columns.
    pca.eigenvectors.resize(dimensions, planes);
    double kept = 0;
    for (int k = 0; k < planes; ++k) {
        pca.eigenvectors.col(k) = solver.eigenvectors().col(dimensions - 1 - k);
        kept += std::max(0.0, solver.eigenvalues()(dimensions - 1 - k));
    }
    const double total = std::max(1e-30, solver.eigenvalues().cwiseMax(0.0).sum());
    pca.retainedVariance = kept / total;
    return pca;
}

// The basis as info.json stores it and as OpenLIME decodes it.
struct QuantizedBasis {
    std::vector<int> bytes;       // the mean, then each plane: info.json's "basis"
    std::vector<double> range;    // per plane
    Eigen::VectorXd meanDecoded;  // what a viewer reads back
    Eigen::MatrixXd basisDecoded;
};

// mean = byte/255, planes = (byte − 127)/range with range = 127/max|e| (Relight's convention),
// so each eigenvector uses the full byte range.
QuantizedBasis quantizeBasis(const PrincipalPlanes& pca) {
    const Eigen::Index dimensions = pca.mean.size();
    const int planes = static_cast<int>(pca.eigenvectors.cols());
    QuantizedBasis basis;
    basis.bytes.reserve(static_cast<std::size_t>((planes + 1) * dimensions));
    basis.meanDecoded.resize(dimensions);
    for (Eigen::Index d = 0; d < dimensions; ++d) {
        const std::uint8_t b = std::max<std::uint8_t>(toByte(pca.mean(d) * 255.0), kMeanFloorByte);
        basis.bytes.push_back(b);
        basis.meanDecoded(d) = b / 255.0;
    }
    basis.range.resize(static_cast<std::size_t>(planes));
    basis.basisDecoded.resize(dimensions, planes);
    for (int k = 0; k < planes; ++k) {
        const double largest = std::max(1e-12, pca.eigenvectors.col(k).cwiseAbs().maxCoeff());
        double& range = basis.range[static_cast<std::size_t>(k)];
        range = 127.0 / largest;
        for (Eigen::Index d = 0; d < dimensions; ++d) {
            const std::uint8_t b = toByte(127.0 + range * pca.eigenvectors(d, k));
            basis.bytes.push_back(b);
            basis.basisDecoded(d, k) = (b - 127.0) / range;
        }
    }
    return basis;
}

// Coefficients by least squares against the quantized basis (not a plain projection on
// the exact one), so the viewer's reconstruction absorbs the basis's rounding.
Eigen::MatrixXf projectOntoBasis(const Eigen::MatrixXf& samples, const QuantizedBasis& basis,
                                 unsigned threads) {
    const Eigen::MatrixXd& decoded = basis.basisDecoded;
    const Eigen::MatrixXd projector =
        (decoded.transpose() * decoded).ldlt().solve(decoded.transpose());
    const Eigen::MatrixXf projectorF = projector.cast<float>();
    const Eigen::VectorXf meanF = basis.meanDecoded.cast<float>();
    Eigen::MatrixXf coefficients(decoded.cols(), samples.cols());
    common::parallelFor(static_cast<std::size_t>(samples.cols()), 4096, threads,
                        [&](std::size_t begin, std::size_t end) {
                            const auto b = static_cast<Eigen::Index>(begin);
                            const auto n = static_cast<Eigen::Index>(end - begin);
                            coefficients.middleCols(b, n).noalias() =
                                projectorF * (samples.middleCols(b, n).colwise() - meanF);
                        });
    return coefficients;
}

// The lowest value each grid node may decode to: kFloor, or the mean's own where that is lower
// (r = 0 then keeps it, as FlooredProjection needs).
Eigen::VectorXd nodeFloors(const QuantizedBasis& basis) {
    return basis.meanDecoded.cwiseMin(kFloor);
}

// The lowest of (decoded value − floor) over the nodes of one pixel's coefficients.
double lowestAboveFloor(const QuantizedBasis& basis, const Eigen::VectorXd& coefficients,
                        const Eigen::VectorXd& floors) {
    return (basis.meanDecoded + basis.basisDecoded * coefficients - floors).minCoeff();
}

// Pixels whose least-squares coefficients decode below a node's floor are solved again under
// the floors (most pixels keep theirs). Returns how many were.
std::size_t floorCoefficients(const Eigen::MatrixXf& samples, const QuantizedBasis& basis,
                              const FlooredProjection& projection, Eigen::MatrixXf& coefficients,
                              unsigned threads) {
    const Eigen::VectorXd floors = nodeFloors(basis);
    const Eigen::VectorXd floorsOffMean = floors - basis.meanDecoded;
    std::atomic<std::size_t> floored{0};
    common::parallelFor(
        static_cast<std::size_t>(samples.cols()), 1024, threads,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const auto p = static_cast<Eigen::Index>(i);
                const Eigen::VectorXd r = coefficients.col(p).cast<double>();
                if (lowestAboveFloor(basis, r, floors) >= 0) {
                    continue;
                }
                const Eigen::VectorXd target = samples.col(p).cast<double>() - basis.meanDecoded;
                coefficients.col(p) = projection.solve(target, floorsOffMean).cast<float>();
                ++floored;
            }
        });
    return floored.load();
}

// Per plane: byte = 255·(c − min)/(max − min); OpenLIME decodes (byte/255 − bias)·scale
// with scale = max − min, bias = −min/scale.
struct PlaneScaling {
    std::vector<double> scale, bias;
};

PlaneScaling scalePlanes(const Eigen::MatrixXf& coefficients) {
    const auto planes = static_cast<std::size_t>(coefficients.rows());
    PlaneScaling scaling{std::vector<double>(planes), std::vector<double>(planes)};
    for (std::size_t k = 0; k < planes; ++k) {
        const auto row = static_cast<Eigen::Index>(k);
        // Zero inside the range: the floored solve starts from r = 0 (floored_projection.h).
        const double lo = std::min(0.0, static_cast<double>(coefficients.row(row).minCoeff()));
        const double hi = std::max(0.0, static_cast<double>(coefficients.row(row).maxCoeff()));
        const double span = std::max(hi - lo, 1e-9);
        scaling.scale[k] = span;
        scaling.bias[k] = -lo / span;
    }
    return scaling;
}

// plane_<j>.jpg: planes 3j, 3j + 1, 3j + 2 as its red, green and blue.
void writePlanes(const std::filesystem::path& dir, int width, int height,
                 const Eigen::MatrixXf& coefficients, const PlaneScaling& scaling, int quality) {
    const Eigen::Index pixels = coefficients.cols();
    const int jpegs = static_cast<int>(coefficients.rows()) / 3;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(pixels) * 3);
    for (int j = 0; j < jpegs; ++j) {
        for (Eigen::Index p = 0; p < pixels; ++p) {
            for (int c = 0; c < 3; ++c) {
                const auto k = static_cast<std::size_t>(j * 3 + c);
                bytes[static_cast<std::size_t>(p) * 3 + c] = toByte(
                    255.0 * (static_cast<double>(coefficients(j * 3 + c, p)) / scaling.scale[k] +
                             scaling.bias[k]));
            }
        }
        writeJpeg(dir / ("plane_" + std::to_string(j) + ".jpg"), width, height, bytes, quality);
    }
}

// The coefficients as a viewer reads them back from the planes written in `dir`.
Eigen::MatrixXf readPlanesBack(const std::filesystem::path& dir, Eigen::Index pixels,
                               const PlaneScaling& scaling) {
    const auto planes = static_cast<Eigen::Index>(scaling.scale.size());
    Eigen::MatrixXf decoded(planes, pixels);
    for (Eigen::Index j = 0; j < planes / 3; ++j) {
        const std::filesystem::path path = dir / ("plane_" + std::to_string(j) + ".jpg");
        const image::FloatImage image = image::readImage(path);
        if (static_cast<Eigen::Index>(image.width) * image.height != pixels || image.channels < 3) {
            throw common::InputError(path, "reads back with another size than it was written");
        }
        const auto channels = static_cast<Eigen::Index>(image.channels);
        for (Eigen::Index p = 0; p < pixels; ++p) {
            for (Eigen::Index c = 0; c < 3; ++c) {
                const auto k = static_cast<std::size_t>(j * 3 + c);
                const double byte = image.pixels[static_cast<std::size_t>(p * channels + c)];
                decoded(j * 3 + c, p) =
                    static_cast<float>((byte - scaling.bias[k]) * scaling.scale[k]);
            }
        }
    }
    return decoded;
}

struct FloorRepair {
    int rounds = 0;          // times the planes were written again
    std::size_t pixels = 0;  // pixels solved again
    // After the rounds: per decoded value (node × colour), its lowest over the pixels.
    Eigen::VectorXd lowest;
};

// Writes the planes; then, while the planes' rounding and JPEG compression take some pixel's
// decoded node values below kFloor / 2, raises that pixel's floors there by the shortfall and
// a margin that grows each time the pixel comes back, solves it again within the planes' byte
// range and writes the planes again. JPEG is deterministic, but a pixel's change moves the
// error of its 8×8 block: hence rounds. On item1 (extended model) 493 pixels were floored and
// 586 solved again over 12 rounds; a fixed margin (no growth) left pixels short after them.
FloorRepair writeFlooredPlanes(const std::filesystem::path& dir, int width, int height,
                               const Eigen::MatrixXf& samples, const QuantizedBasis& basis,
                               const FlooredProjection& projection, Eigen::MatrixXf& coefficients,
                               const PlaneScaling& scaling, const RelightWebOptions& options) {
    const Eigen::Index pixels = coefficients.cols();
    const Eigen::Index dimensions = basis.meanDecoded.size();
    const auto planes = static_cast<Eigen::Index>(scaling.scale.size());
    Eigen::VectorXd lo(planes);
    Eigen::VectorXd hi(planes);
    for (Eigen::Index k = 0; k < planes; ++k) {
        const auto i = static_cast<std::size_t>(k);
        lo(k) = -scaling.bias[i] * scaling.scale[i];
        hi(k) = lo(k) + scaling.scale[i];
    }
    struct Raised {
        Eigen::VectorXd floors;
        int times = 0;
    };
    std::unordered_map<Eigen::Index, Raised> raised;  // pixel → its own floors
    FloorRepair repair;
    for (int round = 0;; ++round) {
        writePlanes(dir, width, height, coefficients, scaling, options.quality);
        const Eigen::MatrixXf decoded = readPlanesBack(dir, pixels, scaling);
        // Every pixel's decoded node values; the shortfalls below kFloor / 2.
        std::vector<std::vector<std::pair<Eigen::Index, double>>> shortfalls(
            static_cast<std::size_t>(pixels));
        std::mutex lowestMutex;
        repair.lowest = Eigen::VectorXd::Constant(dimensions, 1.0);
        common::parallelFor(static_cast<std::size_t>(pixels), 1024, options.threads,
                            [&](std::size_t begin, std::size_t end) {
                                Eigen::VectorXd lowest = Eigen::VectorXd::Constant(dimensions, 1.0);
                                for (std::size_t i = begin; i < end; ++i) {
                                    const auto p = static_cast<Eigen::Index>(i);
                                    const Eigen::VectorXd values =
                                        basis.meanDecoded +
                                        basis.basisDecoded * decoded.col(p).cast<double>();
                                    lowest = lowest.cwiseMin(values);
                                    for (Eigen::Index d = 0; d < dimensions; ++d) {
                                        if (values(d) < kFloor / 2) {
                                            shortfalls[i].emplace_back(d, kFloor - values(d));
                                        }
                                    }
                                }
                                const std::lock_guard<std::mutex> lock(lowestMutex);
                                repair.lowest = repair.lowest.cwiseMin(lowest);
                            });
        std::vector<Eigen::Index> shortPixels;
        for (std::size_t i = 0; i < shortfalls.size(); ++i) {
            if (!shortfalls[i].empty()) {
                shortPixels.push_back(static_cast<Eigen::Index>(i));
            }
        }
        if (shortPixels.empty() || round == kRepairRounds) {
            return repair;
        }
        ++repair.rounds;
        for (const Eigen::Index p : shortPixels) {
            auto [it, added] = raised.try_emplace(p, Raised{nodeFloors(basis), 0});
            repair.pixels += added ? 1 : 0;
            Raised& pixel = it->second;
            ++pixel.times;
            for (const auto& [d, shortfall] : shortfalls[static_cast<std::size_t>(p)]) {
                // No higher than the mean: r = 0 must keep every floor.
                pixel.floors(d) = std::min(basis.meanDecoded(d), pixel.floors(d) + shortfall +
                                                                     kRepairMargin * pixel.times);
            }
        }
        common::parallelFor(
            shortPixels.size(), 16, options.threads, [&](std::size_t begin, std::size_t end) {
                for (std::size_t i = begin; i < end; ++i) {
                    const Eigen::Index p = shortPixels[i];
                    const Eigen::VectorXd target =
                        samples.col(p).cast<double>() - basis.meanDecoded;
                    const Eigen::VectorXd floorsOffMean = raised.at(p).floors - basis.meanDecoded;
                    coefficients.col(p) =
                        projection.solve(target, floorsOffMean, lo, hi).cast<float>();
                }
            });
    }
}

// Every grid value below its node's black level is raised to it.
void liftBlack(Eigen::MatrixXf& samples, const Eigen::VectorXd& black) {
    const Eigen::VectorXf level = black.cast<float>();
    for (Eigen::Index p = 0; p < samples.cols(); ++p) {
        samples.col(p) = samples.col(p).cwiseMax(level);
    }
}

// Per decoded value (node × colour), how far below black the trial encoding decodes the
// pixels that are black there: the 99.9th percentile over them of (black − decoded), PCA,
// rounding and JPEG together.
Eigen::VectorXd blackDrop(const Eigen::MatrixXf& samples, const QuantizedBasis& basis,
                          const Eigen::MatrixXf& decoded, unsigned threads) {
    Eigen::VectorXd result = Eigen::VectorXd::Zero(samples.rows());
    const Eigen::MatrixXf values =
        (basis.basisDecoded.cast<float>() * decoded).colwise() + basis.meanDecoded.cast<float>();
    common::parallelFor(static_cast<std::size_t>(samples.rows()), 1, threads,
                        [&](std::size_t begin, std::size_t end) {
                            std::vector<float> drops;
                            for (std::size_t d = begin; d < end; ++d) {
                                const auto row = static_cast<Eigen::Index>(d);
                                drops.clear();
                                for (Eigen::Index p = 0; p < samples.cols(); ++p) {
                                    if (samples(row, p) <= static_cast<float>(kBlack)) {
                                        drops.push_back(samples(row, p) - values(row, p));
                                    }
                                }
                                if (drops.empty()) {
                                    continue;
                                }
                                const auto rank = static_cast<std::ptrdiff_t>(
                                    0.999 * static_cast<double>(drops.size() - 1));
                                std::nth_element(drops.begin(), drops.begin() + rank, drops.end());
                                result(row) = std::max(0.0f, drops[static_cast<std::size_t>(rank)]);
                            }
                        });
    return result;
}

// The last resort, exact because info.json's basis is not compressed: a node value that the
// rounds left below kFloor / 2 in some pixel is lifted in every pixel, by raising the mean's
// byte there. Returns the largest lift (0 when the rounds sufficed).
double liftMean(QuantizedBasis& basis, const Eigen::VectorXd& lowest) {
    double largest = 0;
    for (Eigen::Index d = 0; d < lowest.size(); ++d) {
        if (lowest(d) >= kFloor / 2) {
            continue;
        }
        const int codes = static_cast<int>(std::ceil((kFloor / 2 - lowest(d)) * 255.0));
        const auto o = static_cast<std::size_t>(d);
        const int lifted = std::min(255, basis.bytes[o] + codes);
        largest = std::max(largest, (lifted - basis.bytes[o]) / 255.0);
        basis.bytes[o] = lifted;
        basis.meanDecoded(d) = lifted / 255.0;
    }
    return largest;
}

void writeInfo(const std::filesystem::path& dir, int width, int height,
               const RelightWebOptions& options, const std::vector<proto::Vec3d>& captureLights,
               const QuantizedBasis& basis, const PlaneScaling& scaling) {
    nlohmann::ordered_json info;
    info["width"] = width;
    info["height"] = height;
    info["format"] = "jpg";
    info["type"] = "bilinear";
    info["resolution"] = options.resolution;
    info["colorspace"] = "mrgb";
    if (!captureLights.empty()) {
        nlohmann::json lights = nlohmann::json::array();
        for (const proto::Vec3d& l : captureLights) {
            // Relight writes three decimals.
            for (const double v : {l.x, l.y, l.z}) {
                lights.push_back(std::round(v * 1000.0) / 1000.0);
            }
        }
        info["lights"] = lights;
    }
    info["nplanes"] = options.planes;
    info["quality"] = options.quality;
    info["colorprofile"] = "sRGB";
    info["generator"] = "vpe export-relight";
    info["basis"] = basis.bytes;
    info["materials"] = nlohmann::json::array({nlohmann::ordered_json{
        {"range", basis.range}, {"scale", scaling.scale}, {"bias", scaling.bias}}});
    std::ofstream file(dir / "info.json");
    file << info.dump() << '\n';
    if (!file) {
        throw common::InputError(dir / "info.json", "cannot write");
    }
}

}  // namespace

// docs/relight-export.md, "What vpe does": grid values, PCA, the quantized basis, the
// coefficients against it (floored), the planes (repaired) and info.json.
RelightWebSummary writeRelightWeb(const std::filesystem::path& folder, int width, int height,
                                  const LightRenderer& render, const RelightWebOptions& options,
                                  const std::vector<proto::Vec3d>& captureLights) {
    validate(width, height, options);
    const BilinearLightGrid grid(options.resolution);
    const Eigen::Index pixels = static_cast<Eigen::Index>(width) * height;
    Eigen::MatrixXf samples = renderGridValues(grid, pixels, render, options);
    common::AtomicFolder output(folder, "info.json", "vpe export-relight");
    const std::filesystem::path& dir = output.temporaryPath();

    // A trial encoding with black at kBlack measures how far below it each node decodes its
    // black pixels; black is then raised at each node to clear that (see kBlack).
    liftBlack(samples, Eigen::VectorXd::Constant(samples.rows(), kBlack));
    {
        const QuantizedBasis trialBasis = quantizeBasis(principalPlanes(samples, options.planes));
        const Eigen::MatrixXf trial = projectOntoBasis(samples, trialBasis, options.threads);
        const PlaneScaling trialScaling = scalePlanes(trial);
        writePlanes(dir, width, height, trial, trialScaling, options.quality);
        const Eigen::MatrixXf trialDecoded = readPlanesBack(dir, pixels, trialScaling);
        const Eigen::VectorXd drop = blackDrop(samples, trialBasis, trialDecoded, options.threads);
        liftBlack(samples, (drop.array() + kFloor).max(kBlack).min(kBlackCap).matrix());
    }

    const PrincipalPlanes pca = principalPlanes(samples, options.planes);
    QuantizedBasis basis = quantizeBasis(pca);
    Eigen::MatrixXf coefficients = projectOntoBasis(samples, basis, options.threads);
    const FlooredProjection projection(basis.basisDecoded);
    const std::size_t floored =
        floorCoefficients(samples, basis, projection, coefficients, options.threads);
    const PlaneScaling scaling = scalePlanes(coefficients);
    const FloorRepair repair = writeFlooredPlanes(dir, width, height, samples, basis, projection,
                                                  coefficients, scaling, options);
    const Eigen::VectorXd meanBefore = basis.meanDecoded;
    const double lift = liftMean(basis, repair.lowest);
    writeInfo(dir, width, height, options, captureLights, basis, scaling);

    RelightWebSummary summary;
    summary.width = width;
    summary.height = height;
    summary.planes = options.planes;
    summary.resolution = options.resolution;
    summary.retainedVariance = pca.retainedVariance;
    summary.flooredPixels = floored;
    summary.repairedPixels = repair.pixels;
    summary.repairRounds = repair.rounds;
    summary.meanLift = lift;
    summary.lowestAtNodes = (repair.lowest + basis.meanDecoded - meanBefore).minCoeff();
    summary.blackLevel = samples.minCoeff();
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        summary.bytes += entry.file_size();
    }
    output.commit();
    return summary;
}

}  // namespace vpe::relight_web
