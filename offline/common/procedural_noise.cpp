// SPDX-License-Identifier: MIT
// Gradient noise from a hash of the lattice point (splitmix64 finalizer).
#include "vpe/common/procedural_noise.h"

#include <cmath>

#include "vpe/common/random_bits.h"

namespace vpe::common {

double GradientNoise::gradientDot(std::int64_t ix, std::int64_t iy, double dx, double dy) const {
    const std::uint64_t h = mixBits(seed_ ^ mixBits(static_cast<std::uint64_t>(ix) * 0x1f1f1f1full +
                                                    static_cast<std::uint64_t>(iy)));
    const double angle = uniformFromBits(h) * 2.0 * M_PI;
    return std::cos(angle) * dx + std::sin(angle) * dy;
}

double GradientNoise::at(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    const double dx = x - fx, dy = y - fy;
    auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    const double u = fade(dx), v = fade(dy);
    const double n00 = gradientDot(ix, iy, dx, dy);
    const double n10 = gradientDot(ix + 1, iy, dx - 1, dy);
    const double n01 = gradientDot(ix, iy + 1, dx, dy - 1);
    const double n11 = gradientDot(ix + 1, iy + 1, dx - 1, dy - 1);
    const double a = n00 + u * (n10 - n00);
    const double b = n01 + u * (n11 - n01);
    return 1.4142 * (a + v * (b - a));  // the 2-D gradient noise range is ±1/√2
}

double GradientNoise::fractal(double x, double y, int octaves) const {
    double sum = 0, amplitude = 0.5, frequency = 1, norm = 0;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * at(x * frequency + 17.3 * o, y * frequency - 9.1 * o);
        norm += amplitude;
        amplitude *= 0.5;
        frequency *= 2;
    }
    return sum / norm;
}

}  // namespace vpe::common
