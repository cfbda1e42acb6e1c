// SPDX-License-Identifier: MIT
// Seeded gradient noise and fractal sums, for the synthetic pottery (synth/) and the noise weight
// maps (texture/): deterministic for a seed and independent of evaluation order, so renders do
// not depend on the thread count.
#pragma once

#include <cstdint>

namespace vpe::common {

class GradientNoise {
public:
    explicit GradientNoise(std::uint64_t seed) : seed_(seed) {}

    // Perlin-style gradient noise in about [-1, 1], smooth (quintic fade).
    double at(double x, double y) const;
    // Fractal sum of `octaves` octaves, each twice the frequency and half the amplitude.
    double fractal(double x, double y, int octaves) const;

private:
    double gradientDot(std::int64_t ix, std::int64_t iy, double dx, double dy) const;
    std::uint64_t seed_;
};

}  // namespace vpe::common
