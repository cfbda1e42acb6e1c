// SPDX-License-Identifier: MIT
// Quilting quality metrics: region correctness, sliced Wasserstein distance, radially
// averaged power spectra (FFTW, PCA by common/principal_axes), seam statistics and verbatim-copy
// areas.
#include "vpe/quilt/quilt_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include <OpenImageIO/imageio.h>
#include <fftw3.h>

#include "vpe/common/fftw_planner.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/principal_axes.h"
#include "vpe/common/random_bits.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::quilt {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

// Indices 0..count-1, or `limit` of them evenly spread when there are more.
std::vector<std::size_t> evenSubset(std::size_t count, std::size_t limit) {
    std::vector<std::size_t> indices;
    const std::size_t n = std::min(count, limit);
    indices.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        indices.push_back(count <= limit ? i : i * count / limit);
    }
    return indices;
}

// The vectors of the given pixels, gathered contiguously.
std::vector<float> gather(const CoefficientImage& image, const std::vector<std::size_t>& pixels) {
    std::vector<float> out(pixels.size() * static_cast<std::size_t>(image.dims));
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::copy_n(image.at(pixels[i]), image.dims, out.data() + i * image.dims);
    }
    return out;
}

std::vector<std::size_t> subsetOf(const std::vector<std::size_t>& pixels, std::size_t limit) {
    std::vector<std::size_t> out;
    for (std::size_t i : evenSubset(pixels.size(), limit)) {
        out.push_back(pixels[i]);
    }
    return out;
}

// W₂² between the empirical distributions of two sorted samples, exactly: the quantile
// functions are step functions with breaks at i/n and j/m, merged on the denominator n·m.
double wassersteinSquared1d(const std::vector<double>& a, const std::vector<double>& b) {
    const std::uint64_t n = a.size(), m = b.size();
    std::uint64_t i = 0, j = 0, t = 0;
    double sum = 0;
    while (i < n && j < m) {
        const std::uint64_t endA = (i + 1) * m, endB = (j + 1) * n;
        const std::uint64_t next = std::min(endA, endB);
        const double d = a[i] - b[j];
        sum += static_cast<double>(next - t) * d * d;
        t = next;
        if (endA == next) {
            ++i;
        }
        if (endB == next) {
            ++j;
        }
    }
    return sum / (static_cast<double>(n) * static_cast<double>(m));
}

// A Gaussian vector from the counter-based stream, normalized: a uniform random direction.
std::vector<double> randomDirection(std::uint64_t seed, int direction, int dims) {
    std::vector<double> v(static_cast<std::size_t>(dims));
    double norm = 0;
    for (int d = 0; d < dims; ++d) {
        const std::uint64_t key =
            mixBits(seed ^ mixBits(static_cast<std::uint64_t>(direction) * 4099 +
                                   static_cast<std::uint64_t>(d)));
        const double u1 = 1.0 - uniformFromBits(key);  // (0, 1]: log is finite
        const double u2 = uniformFromBits(mixBits(key));
        v[static_cast<std::size_t>(d)] = std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2);
        norm += v[static_cast<std::size_t>(d)] * v[static_cast<std::size_t>(d)];
    }
    norm = std::sqrt(norm);
    for (double& x : v) {
        x /= norm;
    }
    return v;
}

// ---- power spectra ------------------------------------------------------------------

// One FFTW plan for h × w real windows, Hann-windowed, with its buffers.
class WindowSpectrum {
public:
    WindowSpectrum(int width, int height) : width_(width), height_(height) {
        in_ = fftwf_alloc_real(static_cast<std::size_t>(width) * height);
        out_ = fftwf_alloc_complex(static_cast<std::size_t>(width / 2 + 1) * height);
        {
            const std::lock_guard lock(fftwPlannerMutex());
            plan_ = fftwf_plan_dft_r2c_2d(height, width, in_, out_, FFTW_ESTIMATE);
        }
        hannX_ = hann(width);
        hannY_ = hann(height);
        windowPower_ = 0;
        for (double wy : hannY_) {
            for (double wx : hannX_) {
                windowPower_ += wy * wy * wx * wx;
            }
        }
        const int side = std::min(width, height);
        binWidth_ = 1.0 / side;
        bins_ = side / 2;
    }
    ~WindowSpectrum() {
        {
            const std::lock_guard lock(fftwPlannerMutex());
            fftwf_destroy_plan(plan_);
        }
        fftwf_free(in_);
        fftwf_free(out_);
    }
    WindowSpectrum(const WindowSpectrum&) = delete;
    WindowSpectrum& operator=(const WindowSpectrum&) = delete;

    // Radial average of the periodogram of `plane` (height × width, row-major) in bins of
    // 1/min(width, height) cycles per pixel; bin 0 (DC, and what mean removal and the window
    // do to it) is dropped, as are frequencies beyond 0.5 (the corners).
    std::vector<double> radialPower(const std::vector<double>& plane) {
        const std::size_t count = plane.size();
        const double mean = std::accumulate(plane.begin(), plane.end(), 0.0) / count;
        for (int y = 0; y < height_; ++y) {
            for (int x = 0; x < width_; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * width_ + x;
                in_[p] =
                    static_cast<float>((plane[p] - mean) * hannY_[static_cast<std::size_t>(y)] *
                                       hannX_[static_cast<std::size_t>(x)]);
            }
        }
        fftwf_execute(plan_);
        std::vector<double> power(static_cast<std::size_t>(bins_), 0.0);
        std::vector<std::size_t> samples(static_cast<std::size_t>(bins_), 0);
        const int columns = width_ / 2 + 1;
        for (int ky = 0; ky < height_; ++ky) {
            const double fy = static_cast<double>(ky <= height_ / 2 ? ky : ky - height_) / height_;
            for (int kx = 0; kx < columns; ++kx) {
                const double fx = static_cast<double>(kx) / width_;
                const auto bin = static_cast<int>(std::sqrt(fx * fx + fy * fy) / binWidth_);
                if (bin < 1 || bin >= bins_) {
                    continue;
                }
                const fftwf_complex& f = out_[static_cast<std::size_t>(ky) * columns + kx];
                const double re = static_cast<double>(f[0]), im = static_cast<double>(f[1]);
                power[static_cast<std::size_t>(bin)] += (re * re + im * im) / windowPower_;
                ++samples[static_cast<std::size_t>(bin)];
            }
        }
        for (int b = 1; b < bins_; ++b) {
            if (samples[static_cast<std::size_t>(b)] > 0) {
                power[static_cast<std::size_t>(b)] /=
                    static_cast<double>(samples[static_cast<std::size_t>(b)]);
            }
        }
        power.erase(power.begin());
        return power;
    }

private:
    static std::vector<double> hann(int n) {
        std::vector<double> w(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            w[static_cast<std::size_t>(i)] = 0.5 - 0.5 * std::cos(2 * kPi * (i + 0.5) / n);
        }
        return w;
    }

    int width_, height_;
    float* in_ = nullptr;
    fftwf_complex* out_ = nullptr;
    fftwf_plan plan_ = nullptr;
    std::vector<double> hannX_, hannY_;
    double windowPower_ = 0;
    double binWidth_ = 0;
    int bins_ = 0;
};

// Mean |log ratio| over components and bins; ε keeps empty bins finite without letting a
// rounding-level power count.
double spectrumDistance(const std::vector<std::vector<double>>& a,
                        const std::vector<std::vector<double>>& b) {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t c = 0; c < a.size(); ++c) {
        double scale = 0;
        for (std::size_t i = 0; i < a[c].size(); ++i) {
            scale += a[c][i] + b[c][i];
        }
        scale /= 2.0 * static_cast<double>(std::max<std::size_t>(a[c].size(), 1));
        const double epsilon = 1e-9 * scale + std::numeric_limits<double>::min();
        for (std::size_t i = 0; i < a[c].size(); ++i) {
            sum += std::fabs(std::log((a[c][i] + epsilon) / (b[c][i] + epsilon)));
            ++count;
        }
    }
    return count > 0 ? sum / static_cast<double>(count) : kNaN;
}

struct Square {
    int x = 0, y = 0, side = 0;
};

// The largest axis-aligned square of mask pixels (the first in raster order of its
// bottom-right corner): side[y][x] = 1 + min(up, left, up-left).
Square largestSquare(const std::vector<std::uint8_t>& mask, int width, int height) {
    std::vector<int> previous(static_cast<std::size_t>(width) + 1, 0), current(previous.size(), 0);
    Square best;
    for (int y = 0; y < height; ++y) {
        current[0] = 0;
        for (int x = 0; x < width; ++x) {
            const std::size_t i = static_cast<std::size_t>(x) + 1;
            if (!mask[static_cast<std::size_t>(y) * width + x]) {
                current[i] = 0;
                continue;
            }
            current[i] = 1 + std::min({previous[i], current[i - 1], previous[i - 1]});
            if (current[i] > best.side) {
                best = {x - current[i] + 1, y - current[i] + 1, current[i]};
            }
        }
        std::swap(previous, current);
    }
    return best;
}

// The leading principal directions (largest variance first) of the given vectors; directions
// without variance are dropped. A direction's sign does not matter here (only powers are
// compared).
std::vector<std::vector<double>> principalDirections(const std::vector<float>& samples, int dims,
                                                     int wanted) {
    const std::size_t count = samples.size() / static_cast<std::size_t>(dims);
    if (count < 2) {
        return {};
    }
    const PrincipalAxes axes = principalAxes(
        count, dims,
        [&](std::size_t i) { return samples.data() + i * static_cast<std::size_t>(dims); },
        AxisSelection{.maxAxes = wanted, .dropBelow = 1e-12});
    std::vector<std::vector<double>> directions;
    for (int j = 0; j < axes.count(); ++j) {
        directions.emplace_back(axes.axes.col(j).data(), axes.axes.col(j).data() + dims);
    }
    return directions;
}

// One window of an image projected on each direction: [direction][y·width + x].
std::vector<std::vector<double>> projectWindow(const CoefficientImage& image, int x0, int y0,
                                               int width, int height,
                                               const std::vector<std::vector<double>>& directions) {
    std::vector<std::vector<double>> planes(
        directions.size(), std::vector<double>(static_cast<std::size_t>(width) * height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float* v = image.at(static_cast<std::size_t>(y0 + y) * image.width + x0 + x);
            for (std::size_t c = 0; c < directions.size(); ++c) {
                double sum = 0;
                for (int d = 0; d < image.dims; ++d) {
                    sum += directions[c][static_cast<std::size_t>(d)] * static_cast<double>(v[d]);
                }
                planes[c][static_cast<std::size_t>(y) * width + x] = sum;
            }
        }
    }
    return planes;
}

void measureSpectrum(const CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                     const std::vector<float>& sourceSamples, const CoefficientImage& output,
                     const QualityOptions& options, RegionQuality& quality) {
    quality.spectrum = quality.spectrumSelf = quality.spectrumRatio = kNaN;
    const Square square = largestSquare(mask, source.width, source.height);
    const int side = std::min(square.side, options.maxSpectrumWindow);
    // Two source windows (the square's top and bottom halves) estimate the spectrum twice
    // independently, which gives the self-reference; output windows have the same shape.
    const int width = std::min(side, output.width);
    const int height = std::min(side / 2, output.height);
    quality.spectrumWindowWidth = width;
    quality.spectrumWindowHeight = height;
    if (width < 8 || height < 8) {
        return;  // too few frequencies to say anything
    }
    const std::vector<std::vector<double>> directions =
        principalDirections(sourceSamples, source.dims, options.spectrumComponents);
    quality.spectrumComponents = static_cast<int>(directions.size());
    if (directions.empty()) {
        return;  // a constant region has no spectrum
    }
    WindowSpectrum spectrum(width, height);
    auto radial = [&](const CoefficientImage& image, int x0, int y0) {
        std::vector<std::vector<double>> power;
        for (const auto& plane : projectWindow(image, x0, y0, width, height, directions)) {
            power.push_back(spectrum.radialPower(plane));
        }
        return power;
    };
    const auto top = radial(source, square.x, square.y);
    const auto bottom = radial(source, square.x, square.y + height);
    quality.spectrumSelf = spectrumDistance(top, bottom);
    const int across = output.width / width, down = output.height / height;
    const std::vector<std::size_t> tiles =
        evenSubset(static_cast<std::size_t>(across) * down,
                   static_cast<std::size_t>(std::max(options.maxSpectrumTiles, 1)));
    double sum = 0;
    for (std::size_t tile : tiles) {
        const auto power = radial(output, static_cast<int>(tile % across) * width,
                                  static_cast<int>(tile / across) * height);
        sum += 0.5 * (spectrumDistance(power, top) + spectrumDistance(power, bottom));
    }
    quality.spectrumTiles = static_cast<int>(tiles.size());
    quality.spectrum = sum / static_cast<double>(tiles.size());
    quality.spectrumRatio = quality.spectrum / quality.spectrumSelf;
}

// ---- positions ------------------------------------------------------------------------

double squaredDifference(const float* a, const float* b, int dims) {
    double sum = 0;
    for (int d = 0; d < dims; ++d) {
        const double diff = static_cast<double>(a[d]) - static_cast<double>(b[d]);
        sum += diff * diff;
    }
    return sum / dims;
}

void measureSeams(const CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                  const CoefficientImage& output, const PositionMap& positions,
                  RegionQuality& quality) {
    double seamSum = 0, interiorSum = 0;
    for (int y = 0; y < output.height; ++y) {
        for (int x = 0; x < output.width; ++x) {
            const std::size_t p = positions.pixel(x, y);
            if (!positions.known(p)) {
                continue;
            }
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx >= output.width || y + dy >= output.height) {
                    continue;
                }
                const std::size_t q = positions.pixel(x + dx, y + dy);
                if (!positions.known(q)) {
                    continue;
                }
                // Same offset: the sources are neighbours in the same direction.
                const bool interior = positions.sourceX[q] - positions.sourceX[p] == dx &&
                                      positions.sourceY[q] - positions.sourceY[p] == dy;
                const double difference =
                    squaredDifference(output.at(p), output.at(q), output.dims);
                if (interior) {
                    interiorSum += difference;
                    ++quality.interiorPairs;
                } else {
                    seamSum += difference;
                    ++quality.seamPairs;
                }
            }
        }
    }
    if (quality.interiorPairs == 0) {
        // No block interior to compare with (a pixel shuffle): every output interior pair
        // would be a neighbour pair of the source region, so take those.
        quality.interiorFromSource = true;
        for (int y = 0; y < source.height; ++y) {
            for (int x = 0; x < source.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * source.width + x;
                if (!mask[p]) {
                    continue;
                }
                if (x + 1 < source.width && mask[p + 1]) {
                    interiorSum += squaredDifference(source.at(p), source.at(p + 1), source.dims);
                    ++quality.interiorPairs;
                }
                if (y + 1 < source.height && mask[p + source.width]) {
                    interiorSum +=
                        squaredDifference(source.at(p), source.at(p + source.width), source.dims);
                    ++quality.interiorPairs;
                }
            }
        }
    }
    quality.seamMsd =
        quality.seamPairs > 0 ? seamSum / static_cast<double>(quality.seamPairs) : kNaN;
    quality.interiorMsd =
        quality.interiorPairs > 0 ? interiorSum / static_cast<double>(quality.interiorPairs) : kNaN;
    quality.seamRatio = quality.interiorMsd > 0 ? quality.seamMsd / quality.interiorMsd : kNaN;
}

std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

void measureLargestCopy(const PositionMap& positions, RegionQuality& quality) {
    const std::size_t count = positions.sourceX.size();
    std::vector<std::size_t> parent(count);
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    auto sameOffset = [&](std::size_t p, std::size_t q, int dx, int dy) {
        return positions.known(p) && positions.known(q) &&
               positions.sourceX[q] - positions.sourceX[p] == dx &&
               positions.sourceY[q] - positions.sourceY[p] == dy;
    };
    for (int y = 0; y < positions.height; ++y) {
        for (int x = 0; x < positions.width; ++x) {
            const std::size_t p = positions.pixel(x, y);
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx < positions.width && y + dy < positions.height) {
                    const std::size_t q = positions.pixel(x + dx, y + dy);
                    if (sameOffset(p, q, dx, dy)) {
                        const std::size_t a = findRoot(parent, p), b = findRoot(parent, q);
                        parent[std::max(a, b)] = std::min(a, b);
                    }
                }
            }
        }
    }
    std::vector<std::size_t> size(count, 0);
    std::size_t bestRoot = 0;
    for (std::size_t p = 0; p < count; ++p) {
        if (!positions.known(p)) {
            continue;
        }
        const std::size_t root = findRoot(parent, p);
        if (++size[root] > quality.largestCopy) {
            quality.largestCopy = size[root];
            bestRoot = root;
        }
    }
    if (quality.largestCopy > 0) {
        const int x = static_cast<int>(bestRoot % static_cast<std::size_t>(positions.width));
        const int y = static_cast<int>(bestRoot / static_cast<std::size_t>(positions.width));
        quality.largestCopyOffsetX = positions.sourceX[bestRoot] - x;
        quality.largestCopyOffsetY = positions.sourceY[bestRoot] - y;
    }
    quality.largestCopyFraction =
        count > 0 ? static_cast<double>(quality.largestCopy) / static_cast<double>(count) : kNaN;
}

}  // namespace

CoefficientImage readCoefficientImage(const std::filesystem::path& model) {
    ModelReader reader(model);
    const ModelInfo& info = reader.info();
    CoefficientImage image;
    image.width = info.width;
    image.height = info.height;
    image.harmonics = info.harmonics;
    image.dims = 3 * proto::coefficientCount(info.harmonics);
    const std::size_t pixels = static_cast<std::size_t>(info.width) * info.height;
    image.values.resize(pixels * image.dims);
    image.valid.resize(pixels);
    ModelRows rows;
    constexpr int kBand = 64;
    for (int y = 0; y < info.height; y += kBand) {
        const int count = std::min(kBand, info.height - y);
        reader.readRows(y, count, rows);
        const std::size_t first = static_cast<std::size_t>(y) * info.width;
        // ModelRows is [pixel][channel][k], the layout of CoefficientImage.
        std::copy(rows.coefficient.begin(), rows.coefficient.end(),
                  image.values.begin() + static_cast<std::ptrdiff_t>(first * image.dims));
        std::copy(rows.valid.begin(), rows.valid.end(),
                  image.valid.begin() + static_cast<std::ptrdiff_t>(first));
    }
    return image;
}

double slicedWasserstein(const float* a, std::size_t countA, const float* b, std::size_t countB,
                         int dims, const SlicedWassersteinOptions& options) {
    if (countA == 0 || countB == 0 || dims <= 0 || options.directions <= 0) {
        return kNaN;
    }
    const std::vector<std::size_t> subsetA = evenSubset(countA, options.maxSamples);
    const std::vector<std::size_t> subsetB = evenSubset(countB, options.maxSamples);
    std::vector<double> squared(static_cast<std::size_t>(options.directions));
    parallelFor(squared.size(), 1, options.threads, [&](std::size_t begin, std::size_t end) {
        std::vector<double> projectedA(subsetA.size()), projectedB(subsetB.size());
        for (std::size_t t = begin; t < end; ++t) {
            const std::vector<double> direction =
                randomDirection(options.seed, static_cast<int>(t), dims);
            auto project = [&](const float* set, const std::vector<std::size_t>& subset,
                               std::vector<double>& projected) {
                for (std::size_t i = 0; i < subset.size(); ++i) {
                    const float* v = set + subset[i] * dims;
                    double sum = 0;
                    for (int d = 0; d < dims; ++d) {
                        sum += direction[static_cast<std::size_t>(d)] * static_cast<double>(v[d]);
                    }
                    projected[i] = sum;
                }
                std::sort(projected.begin(), projected.end());
            };
            project(a, subsetA, projectedA);
            project(b, subsetB, projectedB);
            squared[t] = wassersteinSquared1d(projectedA, projectedB);
        }
    });
    return std::sqrt(std::accumulate(squared.begin(), squared.end(), 0.0) /
                     static_cast<double>(squared.size()));
}

RegionQuality measureRegionQuality(const CoefficientImage& source,
                                   const std::vector<std::uint8_t>& labels, int region,
                                   const CoefficientImage& output, const PositionMap& positions,
                                   const QualityOptions& options) {
    if (output.dims != source.dims) {
        throw InputError("region " + std::to_string(region) + ": the output has " +
                         std::to_string(output.harmonics) + " harmonics, the source " +
                         std::to_string(source.harmonics));
    }
    if (labels.size() != static_cast<std::size_t>(source.width) * source.height ||
        positions.width != output.width || positions.height != output.height) {
        throw InputError("region " + std::to_string(region) +
                         ": labels or positions do not match the model sizes");
    }
    RegionQuality quality;
    quality.region = region;
    quality.outputPixels = static_cast<std::size_t>(output.width) * output.height;

    // The source region: labelled pixels with a valid fit (invalid ones hold zeros).
    std::vector<std::uint8_t> mask(labels.size());
    std::vector<std::size_t> sourcePixels;
    for (std::size_t p = 0; p < labels.size(); ++p) {
        mask[p] = labels[p] == region && source.valid[p] ? 1 : 0;
        if (mask[p]) {
            sourcePixels.push_back(p);
        }
    }
    quality.sourcePixels = sourcePixels.size();

    // Correctness and copy consistency.
    double maxDifference = 0;
    for (std::size_t p = 0; p < quality.outputPixels; ++p) {
        if (!positions.known(p)) {
            continue;
        }
        ++quality.positionedPixels;
        const std::size_t s =
            static_cast<std::size_t>(positions.sourceY[p]) * source.width + positions.sourceX[p];
        if (labels[s] == region) {
            ++quality.correctPixels;
        }
        const float* o = output.at(p);
        const float* v = source.at(s);
        for (int d = 0; d < output.dims; ++d) {
            maxDifference = std::max(
                maxDifference, std::fabs(static_cast<double>(o[d]) - static_cast<double>(v[d])));
        }
    }
    quality.correctness = quality.positionedPixels > 0
                              ? static_cast<double>(quality.correctPixels) /
                                    static_cast<double>(quality.positionedPixels)
                              : kNaN;
    quality.copyMaxDifference = quality.positionedPixels > 0 ? maxDifference : kNaN;

    // Distribution match.
    std::vector<std::size_t> outputPixels;
    for (std::size_t p = 0; p < quality.outputPixels; ++p) {
        if (output.valid[p]) {
            outputPixels.push_back(p);
        }
    }
    const std::size_t limit = options.wasserstein.maxSamples;
    const std::vector<float> outputSamples = gather(output, subsetOf(outputPixels, limit));
    const std::vector<float> sourceSamples = gather(source, subsetOf(sourcePixels, limit));
    const std::size_t half = sourcePixels.size() / 2;
    const std::vector<std::size_t> topHalf(
        sourcePixels.begin(), sourcePixels.begin() + static_cast<std::ptrdiff_t>(half));
    const std::vector<std::size_t> bottomHalf(
        sourcePixels.begin() + static_cast<std::ptrdiff_t>(half), sourcePixels.end());
    const std::vector<float> topSamples = gather(source, subsetOf(topHalf, limit));
    const std::vector<float> bottomSamples = gather(source, subsetOf(bottomHalf, limit));
    SlicedWassersteinOptions wasserstein = options.wasserstein;
    wasserstein.threads = options.threads;
    const auto dims = static_cast<std::size_t>(source.dims);
    quality.wasserstein =
        slicedWasserstein(outputSamples.data(), outputSamples.size() / dims, sourceSamples.data(),
                          sourceSamples.size() / dims, source.dims, wasserstein);
    quality.wassersteinSelf =
        slicedWasserstein(topSamples.data(), topSamples.size() / dims, bottomSamples.data(),
                          bottomSamples.size() / dims, source.dims, wasserstein);
    quality.wassersteinRatio = quality.wasserstein / quality.wassersteinSelf;

    measureSpectrum(source, mask, sourceSamples, output, options, quality);
    measureSeams(source, mask, output, positions, quality);
    measureLargestCopy(positions, quality);
    return quality;
}

}  // namespace vpe::quilt
