// SPDX-License-Identifier: MIT
// Radially averaged power spectra of a quilt against its source region: Hann-windowed tiles
// on the principal components (FFTW; plans under the shared planner lock).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include <fftw3.h>

#include "vpe/common/fftw_planner.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/principal_axes.h"

#include "quality_metrics.h"

namespace vpe::quilt::metrics {

namespace {

// One FFTW plan for h × w real windows, Hann-windowed, with its buffers.
class WindowSpectrum {
public:
    WindowSpectrum(int width, int height) : width_(width), height_(height) {
        in_ = fftwf_alloc_real(static_cast<std::size_t>(width) * height);
        out_ = fftwf_alloc_complex(static_cast<std::size_t>(width / 2 + 1) * height);
        {
            const std::lock_guard lock(common::fftwPlannerMutex());
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
            const std::lock_guard lock(common::fftwPlannerMutex());
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
            w[static_cast<std::size_t>(i)] =
                0.5 - 0.5 * std::cos(2 * std::numbers::pi * (i + 0.5) / n);
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
    const common::PrincipalAxes axes = common::principalAxes(
        count, dims,
        [&](std::size_t i) { return samples.data() + i * static_cast<std::size_t>(dims); },
        common::AxisSelection{.maxAxes = wanted, .dropBelow = 1e-12});
    std::vector<std::vector<double>> directions;
    for (int j = 0; j < axes.count(); ++j) {
        directions.emplace_back(axes.axes.col(j).data(), axes.axes.col(j).data() + dims);
    }
    return directions;
}

// One window of an image projected on each direction: [direction][y·width + x].
std::vector<std::vector<double>> projectWindow(const model::CoefficientImage& image, int x0, int y0,
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

}  // namespace

void measureSpectrum(const model::CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                     const std::vector<float>& sourceSamples, const model::CoefficientImage& output,
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
    auto radial = [&](const model::CoefficientImage& image, int x0, int y0) {
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

}  // namespace vpe::quilt::metrics
