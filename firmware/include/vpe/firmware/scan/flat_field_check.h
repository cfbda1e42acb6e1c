// SPDX-License-Identifier: MIT
// FlatFieldCheck: is each colour capture of the radiometric capture (proto/RADIOMETRY.md) the
// flat field it should be? The scan's measures (frame_check.h), on what flat fields imply:
//   black, white   the lit region: pixels whose luminance (Rec. 709 of R, G, B) white − black
//                  reaches minContrast of full scale; at least minLitFraction must be lit
//                  (refused as not_lit: white captured before the projector showed it);
//   every other    it differs from the capture before it beyond the camera's noise on at
//                  least kMinChangedFraction of the lit pixels, in any channel (refused as
//                  unchanged: a capture exposed before the projector switched repeats the one
//                  before) — the scan's check of a phase step.
// That second check needs every field to differ from the one captured before it by much, so the
// fields are captured in an order that makes sure of it (groups()): black with white, then each
// primary's levels alternating between the lower and upper half of its ladder (16, 143, 32,
// 159, …, 128, 255: consecutive captures at least half the ladder apart, and one of each two at
// half the output or more), then the ramp's exposures alternating between long and short
// (stops 0, 4, 1, 3, 2). The images are written in the sequence's order whatever the capture's.
// Not caught, as for a phase step: a capture exposed while the projector switched between two
// flat fields (partly either).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "vpe/firmware/scan/frame_check.h"
#include "vpe/proto/radiometry_capture.h"

namespace vpe::firmware {

class FlatFieldCheck final : public FrameCheck {
public:
    // `fields`: proto::radiometrySequence's. `noiseSigma`: one frame's noise, in samples of
    // these captures (the scan's estimate, ScanFrameCheck::noiseSigma, scaled to their depth).
    // Throws std::invalid_argument when the sequence does not start with black and white.
    FlatFieldCheck(std::vector<proto::FlatField> fields, const FrameCheckSettings& settings,
                   double noiseSigma);

    // The capture order (above): {black, white}, then one field per group.
    const std::vector<std::vector<std::size_t>>& groups() const override { return groups_; }
    // All images must have one size, depth and three channels.
    FrameVerdict check(std::size_t index, const CameraImage& image) override;

    // Known once black and white were accepted: the lit share of the camera's pixels.
    double litFraction() const;

private:
    std::vector<proto::FlatField> fields_;
    FrameCheckSettings settings_;
    float threshold_ = 1;  // a change beyond the noise, samples
    std::vector<std::vector<std::size_t>> groups_;
    std::vector<std::size_t> groupOf_;  // field index → group index
    int width_ = 0, height_ = 0, maxValue_ = 0;
    std::vector<std::pair<std::size_t, CameraImage>> pending_;  // the current group's captures
    std::vector<std::uint32_t> lit_, candidateLit_;
    std::vector<std::uint16_t> previous_;  // the last accepted capture's samples
};

}  // namespace vpe::firmware
