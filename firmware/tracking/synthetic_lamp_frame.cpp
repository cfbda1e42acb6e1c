// SPDX-License-Identifier: MIT
// SyntheticLampFrame: the room's level plus every spot, point-sampled at pixel centres, plus
// seeded Gaussian noise, rounded and clamped to 8 bits. The noise is drawn with Box–Muller from
// mt19937, whose sequence the standard fixes (std::normal_distribution's is not), so a seed
// gives the same frame with every standard library.
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

namespace vpe::firmware {

namespace {

constexpr int kMaxSide = 4096;
// Levels are clamped to 0…255 in the end; this bound only keeps the sums finite.
constexpr double kMaxLevel = 1e6;

std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

void checkSpot(const SyntheticSpot& spot, const std::string& name) {
    if (!std::isfinite(spot.x) || !std::isfinite(spot.y)) {
        throw std::invalid_argument("synthetic lamp frame: " + name + " has a non-finite position");
    }
    if (!(std::abs(spot.peak) <= kMaxLevel)) {
        throw std::invalid_argument("synthetic lamp frame: " + name +
                                    ".peak must be within ±1e6, got " + numberText(spot.peak));
    }
    if (!(std::isfinite(spot.radius) && spot.radius > 0.0 && spot.radius <= kMaxSide)) {
        throw std::invalid_argument("synthetic lamp frame: " + name +
                                    ".radius must be in (0, 4096], got " + numberText(spot.radius));
    }
}

// Adds the spot over the box where it is above 1/1000 of its peak (3.7 σ).
void addSpot(std::vector<double>& image, int width, int height, const SyntheticSpot& spot) {
    const double reach = 3.7 * spot.radius;
    const int x0 = std::max(0, static_cast<int>(std::floor(spot.x - reach)));
    const int x1 = std::min(width - 1, static_cast<int>(std::ceil(spot.x + reach)));
    const int y0 = std::max(0, static_cast<int>(std::floor(spot.y - reach)));
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(spot.y + reach)));
    const double inverseTwoSigmaSquared = 1.0 / (2.0 * spot.radius * spot.radius);
    for (int y = y0; y <= y1; ++y) {
        const double dy = y - spot.y;
        for (int x = x0; x <= x1; ++x) {
            const double dx = x - spot.x;
            image[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)] +=
                spot.peak * std::exp(-(dx * dx + dy * dy) * inverseTwoSigmaSquared);
        }
    }
}

}  // namespace

LuminanceFrame SyntheticLampFrame::render() const {
    if (width < 1 || width > kMaxSide || height < 1 || height > kMaxSide) {
        throw std::invalid_argument(
            "synthetic lamp frame: size must be within 1…4096 × 1…4096, "
            "got " +
            std::to_string(width) + "x" + std::to_string(height));
    }
    if (!(std::abs(background) <= kMaxLevel)) {
        throw std::invalid_argument("synthetic lamp frame: background must be within ±1e6, got " +
                                    numberText(background));
    }
    if (!(noiseSigma >= 0.0 && noiseSigma <= kMaxLevel)) {
        throw std::invalid_argument("synthetic lamp frame: noise must be in [0, 1e6], got " +
                                    numberText(noiseSigma));
    }
    if (lamp) {
        checkSpot(*lamp, "lamp");
    }
    for (std::size_t i = 0; i < distractors.size(); ++i) {
        checkSpot(distractors[i], "distractors[" + std::to_string(i) + "]");
    }

    const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    std::vector<double> image;
    image.assign(count, background);
    for (const SyntheticSpot& distractor : distractors) {
        addSpot(image, width, height, distractor);
    }
    if (lamp) {
        addSpot(image, width, height, *lamp);
    }

    if (noiseSigma > 0.0) {
        std::mt19937 random(seed);
        // Uniform in (0, 1]: 32 random bits, never 0 so that log() is finite.
        const auto uniform = [&random] {
            return (static_cast<double>(random()) + 1.0) / 4294967296.0;
        };
        for (std::size_t i = 0; i < count; i += 2) {
            const double radius = noiseSigma * std::sqrt(-2.0 * std::log(uniform()));
            const double angle = 2.0 * std::numbers::pi * uniform();
            image[i] += radius * std::cos(angle);
            if (i + 1 < count) {
                image[i + 1] += radius * std::sin(angle);
            }
        }
    }

    LuminanceFrame frame;
    frame.width = width;
    frame.height = height;
    frame.pixels.assign(count, 0);
    for (std::size_t i = 0; i < count; ++i) {
        frame.pixels[i] = static_cast<std::uint8_t>(std::lround(std::clamp(image[i], 0.0, 255.0)));
    }
    return frame;
}

}  // namespace vpe::firmware
