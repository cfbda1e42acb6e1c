// SPDX-License-Identifier: MIT
// The simulated sensor: exposure, shot and read noise, response, quantization.
#include "sensor_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "vpe/renderer/cpu/parallel_rows.h"

namespace vpe::renderer::procam {

namespace {

constexpr double kPi = 3.14159265358979323846;

// SplitMix64's finalizer: a counter-based generator, one independent stream per key.
std::uint64_t mix(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// A standard normal deviate for a key (Box–Muller on two uniforms in (0, 1]).
double gaussian(std::uint64_t key) {
    const std::uint64_t a = mix(key), b = mix(key ^ 0xD1B54A32D192ED03ull);
    const double u1 = (static_cast<double>(a >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = static_cast<double>(b >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

}  // namespace

CameraFrame exposeSensor(const SimulatedCamera& camera, const RgbImage& radiance,
                         std::uint64_t frame, int threads) {
    const proto::PinholeCamera& c = camera.camera;
    if (radiance.width != c.width || radiance.height != c.height) {
        throw std::invalid_argument(
            "procam simulator: the radiance image is not the camera's size");
    }
    CameraFrame out;
    out.width = c.width;
    out.height = c.height;
    out.channels = camera.monochrome ? 1 : 3;
    out.bits = camera.bits;
    out.samples.assign(radiance.pixelCount() * static_cast<std::size_t>(out.channels), 0);
    const double levels = out.maxValue();
    const double fullWell = camera.fullWellElectrons;
    const double readNoise = camera.readNoiseElectrons;
    const std::uint64_t stream = mix(camera.seed ^ mix(frame));
    forEachRow(c.height, threads, [&](int y) {
        for (int x = 0; x < c.width; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(y) * c.width + x;
            const float* rgb = radiance.pixel(x, y);
            for (int channel = 0; channel < out.channels; ++channel) {
                const double light = camera.monochrome ? luminance709(rgb[0], rgb[1], rgb[2])
                                                       : static_cast<double>(rgb[channel]);
                double signal = camera.exposure * std::max(light, 0.0);
                if (fullWell > 0) {
                    const double electrons = signal * fullWell;
                    const double sigma = std::sqrt(electrons + readNoise * readNoise);
                    const std::uint64_t key =
                        stream ^ mix(pixel * 4 + static_cast<std::uint64_t>(channel));
                    signal = (electrons + sigma * gaussian(key)) / fullWell;
                }
                signal = std::clamp(signal + camera.blackLevel, 0.0, 1.0);
                const double value = camera.response == CameraResponse::kGamma
                                         ? std::pow(signal, 1.0 / camera.gamma)
                                         : signal;
                out.samples[pixel * static_cast<std::size_t>(out.channels) +
                            static_cast<std::size_t>(channel)] =
                    static_cast<std::uint16_t>(std::lround(value * levels));
            }
        }
    });
    return out;
}

}  // namespace vpe::renderer::procam
