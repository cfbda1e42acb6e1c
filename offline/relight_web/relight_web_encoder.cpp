// SPDX-License-Identifier: MIT
// Encoding a relightable picture as a Relight web RTI (bilinear grid, mrgb PCA planes).
#include "vpe/relight_web/relight_web_encoder.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <Eigen/Dense>
#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/relight_web/bilinear_light_grid.h"

namespace vpe::relight_web {

namespace {

// Pixels the covariance is estimated from: enough for a stable basis of a few hundred
// dimensions, few enough that a large picture does not cost minutes.
constexpr std::size_t kCovarianceSamples = 262144;

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
        const std::uint8_t b = toByte(pca.mean(d) * 255.0);
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
        const double lo = coefficients.row(row).minCoeff();
        const double hi = coefficients.row(row).maxCoeff();
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
// coefficients against it, the planes and info.json.
RelightWebSummary writeRelightWeb(const std::filesystem::path& folder, int width, int height,
                                  const LightRenderer& render, const RelightWebOptions& options,
                                  const std::vector<proto::Vec3d>& captureLights) {
    validate(width, height, options);
    const BilinearLightGrid grid(options.resolution);
    const Eigen::Index pixels = static_cast<Eigen::Index>(width) * height;
    const Eigen::MatrixXf samples = renderGridValues(grid, pixels, render, options);
    const PrincipalPlanes pca = principalPlanes(samples, options.planes);
    const QuantizedBasis basis = quantizeBasis(pca);
    const Eigen::MatrixXf coefficients = projectOntoBasis(samples, basis, options.threads);
    const PlaneScaling scaling = scalePlanes(coefficients);

    common::AtomicFolder output(folder, "info.json", "vpe export-relight");
    const std::filesystem::path& dir = output.temporaryPath();
    writePlanes(dir, width, height, coefficients, scaling, options.quality);
    writeInfo(dir, width, height, options, captureLights, basis, scaling);

    RelightWebSummary summary;
    summary.width = width;
    summary.height = height;
    summary.planes = options.planes;
    summary.resolution = options.resolution;
    summary.retainedVariance = pca.retainedVariance;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        summary.bytes += entry.file_size();
    }
    output.commit();
    return summary;
}

}  // namespace vpe::relight_web
