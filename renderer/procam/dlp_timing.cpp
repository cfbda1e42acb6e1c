// SPDX-License-Identifier: MIT
// A DLP projector's bit-planes integrated over a camera's exposure window.
#include "vpe/renderer/procam/dlp_timing.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vpe::renderer::procam {

namespace {

// SplitMix64's finalizer, as the sensor's noise (sensor_noise.cpp).
std::uint64_t mix(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// ∫₀ᵘ of the mirror state of 8-bit `code` over u ∈ [0, 1] frame periods.
double onWithinFrame(int code, DlpBitOrder order, double u) {
    double at = 0, on = 0;
    for (int i = 0; i < 8; ++i) {
        const int plane = order == DlpBitOrder::kMsbFirst ? 7 - i : i;
        const double length = static_cast<double>(1 << plane) / 255.0;
        if ((code >> plane & 1) != 0) {
            on += std::clamp(u - at, 0.0, length);
        }
        at += length;
    }
    return on;
}

// ∫₀ᵗ of the mirror state for any t ≥ 0: whole frames, then part of one.
double onUntil(int code, DlpBitOrder order, double t) {
    const double frames = std::floor(t);
    return frames * code / 255.0 + onWithinFrame(code, order, t - frames);
}

double windowMean(int code, const DlpTiming& timing, double start) {
    if (code == 0 || code == 255) {
        return code / 255.0;
    }
    const double end = start + timing.exposureFrames;
    return (onUntil(code, timing.order, end) - onUntil(code, timing.order, start)) /
           timing.exposureFrames;
}

}  // namespace

double dlpWindowDuty(const DlpTiming& timing, double duty, double start) {
    const double code = std::clamp(duty, 0.0, 1.0) * 255.0;
    const int low = std::min(static_cast<int>(code), 254);
    const double fraction = code - low;
    return (1 - fraction) * windowMean(low, timing, start) +
           fraction * windowMean(low + 1, timing, start);
}

double dlpWindowStart(std::uint64_t seed, std::uint64_t frame) {
    // A stream of its own: the sensor's keys are mix(seed ^ mix(frame)) ^ mix(pixel, channel).
    const std::uint64_t key = mix(mix(seed ^ 0x44C9F1A3B5D7E203ull) ^ mix(frame));
    return static_cast<double>(key >> 11) * 0x1.0p-53;
}

}  // namespace vpe::renderer::procam
