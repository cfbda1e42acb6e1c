// SPDX-License-Identifier: MIT
// The measures the scan's frame check and the radiometric capture's share: the lit region
// (white − black) and whether a capture changed since the one before it (a stale capture
// repeats it), with their refusals worded once.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vpe/firmware/scan/frame_check.h"

namespace vpe::firmware::frame_measures {

// "12.5%".
std::string percent(double fraction);

// The pixels where white − black reaches `floor` (one value per pixel).
std::vector<std::uint32_t> litPixels(std::span<const float> white, std::span<const float> black,
                                     float floor);

// kNotLit when `lit` of `pixels` is empty or below settings.minLitFraction; passed otherwise.
FrameVerdict litVerdict(std::size_t lit, std::size_t pixels, const FrameCheckSettings& settings);

// A change beyond one frame's noise σ: the difference of two frames has √2 σ; at least one
// sample step.
inline float changeThreshold(double noiseSigma) {
    return static_cast<float>(std::max(3.0 * std::sqrt(2.0) * noiseSigma, 1.0));
}

// The share of the `lit` pixels where any of the `channels` interleaved samples of `image`
// differs from `previous` by more than `threshold`.
template <typename Sample>
double changedShare(std::span<const Sample> image, std::span<const Sample> previous, int channels,
                    const std::vector<std::uint32_t>& lit, float threshold) {
    if (lit.empty()) {
        return 0.0;
    }
    const auto stride = static_cast<std::size_t>(channels);
    std::size_t changed = 0;
    for (const std::uint32_t p : lit) {
        bool moved = false;
        for (std::size_t c = 0; c < stride && !moved; ++c) {
            const std::size_t i = p * stride + c;
            moved = std::abs(static_cast<float>(image[i]) - static_cast<float>(previous[i])) >
                    threshold;
        }
        changed += moved ? 1 : 0;
    }
    return static_cast<double>(changed) / static_cast<double>(lit.size());
}

// kUnchanged when `changed` is below kMinChangedFraction: `what` names the capture ("phase
// step", "flat field").
FrameVerdict changedVerdict(double changed, const std::string& what);

}  // namespace vpe::firmware::frame_measures
