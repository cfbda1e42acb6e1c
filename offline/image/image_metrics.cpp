// SPDX-License-Identifier: MIT
// PSNR and SSIM on 8-bit sRGB pictures.
#include "vpe/image/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "vpe/proto/srgb.h"

namespace vpe::image {

namespace {

constexpr int kRadius = 5;  // an 11 × 11 window
constexpr double kSigma = 1.5;
constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);

void checkSizes(const Rgb8Image& a, const Rgb8Image& b, const std::vector<std::uint8_t>* mask) {
    const std::size_t pixels =
        static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
    if (a.width != b.width || a.height != b.height || a.values.size() != 3 * pixels ||
        b.values.size() != 3 * pixels || (mask != nullptr && mask->size() != pixels)) {
        throw std::invalid_argument("image metrics: pictures and mask differ in size");
    }
}

// The normalized 1-D Gaussian (the 2-D window is its outer product, summing to 1).
std::array<double, 2 * kRadius + 1> gaussianWindow() {
    std::array<double, 2 * kRadius + 1> w{};
    double sum = 0;
    for (int k = -kRadius; k <= kRadius; ++k) {
        w[static_cast<std::size_t>(k + kRadius)] = std::exp(-0.5 * k * k / (kSigma * kSigma));
        sum += w[static_cast<std::size_t>(k + kRadius)];
    }
    for (double& v : w) {
        v /= sum;
    }
    return w;
}

// Separable filtering of the five moment planes (a, b, a², b², ab), valid part only.
std::vector<double> channelSsim(const Rgb8Image& a, const Rgb8Image& b, int channel) {
    const int width = a.width, height = a.height;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const auto window = gaussianWindow();
    constexpr int kPlanes = 5;
    std::vector<double> source(pixels * kPlanes), rows(pixels * kPlanes, 0.0);
    for (std::size_t p = 0; p < pixels; ++p) {
        const double x = a.values[3 * p + static_cast<std::size_t>(channel)];
        const double y = b.values[3 * p + static_cast<std::size_t>(channel)];
        const double planes[kPlanes] = {x, y, x * x, y * y, x * y};
        std::copy(planes, planes + kPlanes, source.begin() + static_cast<long>(p * kPlanes));
    }
    for (int y = 0; y < height; ++y) {
        for (int x = kRadius; x < width - kRadius; ++x) {
            double* out = rows.data() + (static_cast<std::size_t>(y) * width + x) * kPlanes;
            for (int k = -kRadius; k <= kRadius; ++k) {
                const double w = window[static_cast<std::size_t>(k + kRadius)];
                const double* in =
                    source.data() + (static_cast<std::size_t>(y) * width + x + k) * kPlanes;
                for (int q = 0; q < kPlanes; ++q) {
                    out[q] += w * in[q];
                }
            }
        }
    }
    std::vector<double> map(pixels, std::numeric_limits<double>::quiet_NaN());
    for (int y = kRadius; y < height - kRadius; ++y) {
        for (int x = kRadius; x < width - kRadius; ++x) {
            double m[kPlanes] = {0, 0, 0, 0, 0};
            for (int k = -kRadius; k <= kRadius; ++k) {
                const double w = window[static_cast<std::size_t>(k + kRadius)];
                const double* in =
                    rows.data() + (static_cast<std::size_t>(y + k) * width + x) * kPlanes;
                for (int q = 0; q < kPlanes; ++q) {
                    m[q] += w * in[q];
                }
            }
            const double muA = m[0], muB = m[1];
            const double varA = m[2] - muA * muA, varB = m[3] - muB * muB;
            const double covariance = m[4] - muA * muB;
            map[static_cast<std::size_t>(y) * width + x] =
                ((2 * muA * muB + kC1) * (2 * covariance + kC2)) /
                ((muA * muA + muB * muB + kC1) * (varA + varB + kC2));
        }
    }
    return map;
}

}  // namespace

Rgb8Image toSrgb8(const std::vector<float>& linearRgb, int width, int height, double exposure) {
    std::vector<std::uint8_t> values(linearRgb.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double v = std::clamp(static_cast<double>(linearRgb[i]) * exposure, 0.0, 1.0);
        values[i] = static_cast<std::uint8_t>(std::lround(255.0 * proto::linearToSrgb(v)));
    }
    return {width, height, std::move(values)};
}

double psnr(const Rgb8Image& a, const Rgb8Image& b, const std::vector<std::uint8_t>& mask) {
    checkSizes(a, b, &mask);
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < mask.size(); ++p) {
        if (!mask[p]) {
            continue;
        }
        for (std::size_t c = 0; c < 3; ++c) {
            const double d = static_cast<double>(a.values[3 * p + c]) - b.values[3 * p + c];
            sum += d * d;
        }
        count += 3;
    }
    if (count == 0) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const double mse = sum / static_cast<double>(count);
    return mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse)
                   : std::numeric_limits<double>::infinity();
}

std::vector<double> ssimMap(const Rgb8Image& a, const Rgb8Image& b, int channel) {
    checkSizes(a, b, nullptr);
    if (channel < 0 || channel > 2) {
        throw std::invalid_argument("ssimMap: channel must be 0, 1 or 2");
    }
    return channelSsim(a, b, channel);
}

double meanSsim(const Rgb8Image& a, const Rgb8Image& b, const std::vector<std::uint8_t>& mask) {
    checkSizes(a, b, &mask);
    double sum = 0;
    std::size_t count = 0;
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> map = channelSsim(a, b, c);
        for (std::size_t p = 0; p < mask.size(); ++p) {
            if (mask[p] && !std::isnan(map[p])) {
                sum += map[p];
                ++count;
            }
        }
    }
    return count ? sum / static_cast<double>(count) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace vpe::image
