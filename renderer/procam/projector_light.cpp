// SPDX-License-Identifier: MIT
// The projector's light for one frame: response, a DLP's bit-planes over the exposure window,
// black level, separable Gaussian defocus.
#include "projector_light.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vpe::renderer::procam {

namespace {

// out = in ∗ g along one axis (stride between neighbours), clamp to edge.
void blurAxis(std::vector<float>& values, int width, int height, bool alongRows,
              const std::vector<float>& kernel) {
    const int radius = static_cast<int>(kernel.size() / 2);
    const int lines = alongRows ? height : width;
    const int extent = alongRows ? width : height;
    std::vector<float> line(static_cast<std::size_t>(extent) * 3);
    for (int l = 0; l < lines; ++l) {
        const auto index = [&](int i) {
            const int x = alongRows ? i : l, y = alongRows ? l : i;
            return (static_cast<std::size_t>(y) * width + x) * 3;
        };
        for (int i = 0; i < extent; ++i) {
            float sum[3] = {0, 0, 0};
            for (int k = -radius; k <= radius; ++k) {
                const std::size_t at = index(std::clamp(i + k, 0, extent - 1));
                const float w = kernel[static_cast<std::size_t>(k + radius)];
                sum[0] += w * values[at];
                sum[1] += w * values[at + 1];
                sum[2] += w * values[at + 2];
            }
            std::copy(sum, sum + 3, line.begin() + std::ptrdiff_t(3 * i));
        }
        for (int i = 0; i < extent; ++i) {
            std::copy_n(line.begin() + std::ptrdiff_t(3 * i), 3,
                        values.begin() + std::ptrdiff_t(index(i)));
        }
    }
}

}  // namespace

ProjectorLight::ProjectorLight(const SimulatedProjector& projector, const RgbImage& levels,
                               std::optional<double> windowStart)
    : width_(projector.camera.width), height_(projector.camera.height) {
    if (levels.width != width_ || levels.height != height_ ||
        levels.values.size() != levels.pixelCount() * 3) {
        throw std::invalid_argument("procam simulator: the image is " +
                                    std::to_string(levels.width) + "x" +
                                    std::to_string(levels.height) + ", the projector " +
                                    std::to_string(width_) + "x" + std::to_string(height_));
    }
    // The response is a function of 256 codes in practice; a table per channel keeps a frame's
    // cost at a lookup per value for 8-bit patterns, exact for the others.
    std::array<std::array<float, 256>, 3> table{};
    // A DLP's degamma is in its bit-plane weights: the mirror's duty is the response's output,
    // and the exposure window sees its bit-planes (dlp_timing.h). The leak is there throughout.
    const bool dlp = projector.dlp.enabled() && windowStart.has_value();
    const auto relative = [&](int channel, double level) {
        const double black = projector.blackLevel[static_cast<std::size_t>(channel)];
        double duty = projector.response.output(channel, level);
        if (dlp) {
            duty = dlpWindowDuty(projector.dlp, duty, *windowStart);
        }
        return static_cast<float>(black + (1 - black) * duty);
    };
    for (int channel = 0; channel < 3; ++channel) {
        for (int code = 0; code < 256; ++code) {
            table[static_cast<std::size_t>(channel)][static_cast<std::size_t>(code)] =
                relative(channel, code / 255.0);
        }
    }
    output_.resize(levels.values.size());
    for (std::size_t i = 0; i < levels.values.size(); ++i) {
        const int channel = static_cast<int>(i % 3);
        const double level = std::clamp(static_cast<double>(levels.values[i]), 0.0, 1.0);
        const double code = level * 255.0;
        const auto rounded = static_cast<int>(std::lround(code));
        output_[i] =
            std::abs(code - rounded) < 1e-4
                ? table[static_cast<std::size_t>(channel)][static_cast<std::size_t>(rounded)]
                : relative(channel, level);
    }
    const auto& m = projector.mixing;
    if (m != std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}) {
        for (std::size_t i = 0; i < output_.size(); i += 3) {
            const double r = output_[i], g = output_[i + 1], b = output_[i + 2];
            for (std::size_t k = 0; k < 3; ++k) {
                output_[i + k] =
                    static_cast<float>(m[3 * k] * r + m[3 * k + 1] * g + m[3 * k + 2] * b);
            }
        }
    }
    if (projector.blurPixels > 0) {
        const double sigma = projector.blurPixels;
        const int radius = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
        std::vector<float> kernel(static_cast<std::size_t>(2 * radius + 1));
        double total = 0;
        for (int k = -radius; k <= radius; ++k) {
            const double w = std::exp(-0.5 * k * k / (sigma * sigma));
            kernel[static_cast<std::size_t>(k + radius)] = static_cast<float>(w);
            total += w;
        }
        for (float& w : kernel) {
            w = static_cast<float>(static_cast<double>(w) / total);
        }
        blurAxis(output_, width_, height_, true, kernel);
        blurAxis(output_, width_, height_, false, kernel);
    }
}

std::array<float, 3> ProjectorLight::at(float x, float y) const {
    x = std::clamp(x, 0.0f, static_cast<float>(width_ - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(height_ - 1));
    const int x0 = std::min(static_cast<int>(x), width_ - 1),
              y0 = std::min(static_cast<int>(y), height_ - 1);
    const int x1 = std::min(x0 + 1, width_ - 1), y1 = std::min(y0 + 1, height_ - 1);
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    const auto value = [&](int px, int py, std::size_t c) {
        return output_[(static_cast<std::size_t>(py) * width_ + px) * 3 + c];
    };
    std::array<float, 3> out{};
    for (std::size_t c = 0; c < 3; ++c) {
        const float top = value(x0, y0, c) + fx * (value(x1, y0, c) - value(x0, y0, c));
        const float bottom = value(x0, y1, c) + fx * (value(x1, y1, c) - value(x0, y1, c));
        out[c] = top + fy * (bottom - top);
    }
    return out;
}

}  // namespace vpe::renderer::procam
