// SPDX-License-Identifier: MIT
// The steps of decoding that the phase-shifting decoder (pattern_decoder.cpp) and the Gray-code
// one (gray_code_decoder.cpp) share: the camera's noise from residuals that must be zero, the
// mixed pixels at steps between surfaces, and the tally of the pixels' statuses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "vpe/structured_light/pattern_decoder.h"

namespace vpe::structured_light::detail {

// Shared by both decoders: an undecoded coordinate, the pixels per parallel task, and the
// per-pixel, per-axis markers of a Gray bit left open.
inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr std::size_t kGrain = 4096;
inline constexpr int kNoUncertainBit = -1;
inline constexpr int kTooManyUncertainBits = -2;

// σ² = a + b·signal from residuals r = (two images) − (two others) that would be zero without
// noise, at levels x = the sum of one pair (0..2): var(r) = 4a + 2b·x, a line through the binned
// variances (robust: the median absolute deviation per bin). `quantum` is the camera's step:
// a capture without measurable noise still has its quantization's.
NoiseModel fitNoiseModel(const std::vector<double>& level, const std::vector<double>& residual,
                         double quantum);

// What the two axes have read so far, per pixel.
struct AxisCode {
    std::vector<std::uint32_t> code;     // the Gray bits as read, above the lowest shown
    std::vector<std::int8_t> uncertain;  // the one bit the noise left open, or the markers
};

// Refuses (InputError naming the manifest) a capture whose certain codes reach beyond the
// declared projector on more than 2 % of an axis' certain codes, among the pixels not kDark: a
// wrong --projector or --step, which the image count cannot tell (1024x768 step 1 and 1920x1080
// step 2 both show 42 images).
void checkCodesFitTheProjector(const ScanCapture& capture, const AxisCode& columns,
                               const AxisCode& rows, const std::vector<DecodeStatus>& status);

// The camera's encoding γ (value = signal^(1/γ)) that makes a pattern and its inverse add up to
// white + black, as light does: fitted on the pixels the pair lights partly (a stripe's edge,
// the projector's blur), where a curve breaks the sum. 1 when the capture is linear (within
// 0.05) or shows too few such pixels to tell.
double fitCameraGamma(const std::vector<float>& white, const std::vector<float>& black,
                      const std::vector<float>& on, const std::vector<float>& off);

// Every value v ← v^γ (clipped to [0, 1]): the camera's codes back to its signal.
void linearize(std::vector<float>& values, double gamma);

// Marks as kEdge (and undecodes) the decoded pixels where the coordinates bend beyond maxBend
// projector pixels one way and the other way at a neighbour, along a row or a column. A bend
// through a pixel the Gray bin placed (PositionSource::kGrayBin) may add two bins' rounding.
void markMixedPixels(DecodedScan& scan, double maxBend, double grayBinWidth, unsigned threads);

// statusCounts, sourceCounts, decoded and lit (`lit`: the pixels the projector's direct light
// reaches).
void countStatuses(DecodedScan& scan, std::size_t lit);

// A Gray code without phase images: whole Gray bins (gray_code_decoder.cpp).
DecodedScan decodeGrayCode(const ScanCapture& capture, const DecodeOptions& options);

}  // namespace vpe::structured_light::detail
