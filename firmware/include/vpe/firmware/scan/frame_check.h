// SPDX-License-Identifier: MIT
// ScanFrameCheck: is each capture of a scan the pattern it should be? A camera frame exposed
// before the projector switched (stale: the projector's latency was longer than the wait) or
// while it switched shows the wrong pattern, and the decoder cannot tell: it would decode wrong
// codes. The checks use only what the sequence itself implies, whatever the installation:
//   white, black   they define the lit region: pixels where white − black reaches minContrast
//                  of full scale; at least minLitFraction of the camera must be lit;
//   Gray pattern   its lit pixels are mostly near black or near white (bimodal), and with its
//                  inverse it adds up to white + black (light adds: pattern + inverse = white);
//   phase step     it differs from the previous capture beyond the camera's noise (measured on
//                  the Gray pairs), as every step moves the sinusoid.
// Patterns are checked in groups that are captured, and retried, together: white with black, a
// Gray pattern with its inverse, each phase step alone. FrameCheck is what the capture loop
// (capture_loop.h) asks of this check and of the radiometric capture's (flat_field_check.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vpe/firmware/scan/camera_image.h"
#include "vpe/proto/structured_light.h"

namespace vpe::firmware {

struct FrameCheckSettings {
    double minContrast = 0.05;      // white − black, share of full scale, for a pixel to be lit
    double minLitFraction = 0.005;  // share of the camera's pixels that must be lit
    double tolerance = 0.2;         // share of the lit pixels allowed to disagree
};

// Why a capture was refused (the report counts each).
enum class FrameProblem : std::uint8_t {
    kNone,
    kNotLit,        // white − black too small almost everywhere
    kNotBimodal,    // a Gray pattern's pixels between black and white
    kPairMismatch,  // pattern + inverse is not white + black
    kUnchanged,     // a phase step that looks like the step before it
};
inline constexpr int kFrameProblemCount = 5;
// "not_lit", "not_bimodal", "pair_mismatch", "unchanged" ("" for kNone).
const char* frameProblemName(FrameProblem problem);

struct FrameVerdict {
    FrameProblem problem = FrameProblem::kNone;
    std::string detail;  // a phrase naming the measure and its limit; "" when passed

    bool passed() const { return problem == FrameProblem::kNone; }
};

// What the capture loop asks of a check: the sequence's indices in the groups that are captured,
// and retried, together, in the order they are captured; and a verdict on each capture.
class FrameCheck {
public:
    virtual ~FrameCheck() = default;

    virtual const std::vector<std::vector<std::size_t>>& groups() const = 0;
    // Checks the capture of image `index`, given in the groups' order; the first of a group
    // starts it afresh (a retry gives the group again from its first), and the group's last,
    // when it passes, makes the group accepted: what later checks compare with.
    virtual FrameVerdict check(std::size_t index, const CameraImage& image) = 0;
};

// A phase step passes when at least this share of the lit pixels changed beyond the noise (a
// stale capture changes none but noise: ~0.3%).
inline constexpr double kMinChangedFraction = 0.05;

class ScanFrameCheck final : public FrameCheck {
public:
    ScanFrameCheck(const proto::StructuredLightSequence& sequence,
                   const FrameCheckSettings& settings);

    // The sequence's indices in groups, in order.
    const std::vector<std::vector<std::size_t>>& groups() const override { return groups_; }

    // Checks the capture of pattern `index`. Patterns are given in the sequence's order; the
    // first pattern of a group starts it afresh (a retry gives the group again from its first),
    // and a group's last pattern, when it passes, makes the group accepted: its captures are
    // what later checks compare with. All images must have one size, and one channel.
    FrameVerdict check(std::size_t index, const CameraImage& image) override;

    // Known once white and black were accepted: the lit share of the camera's pixels.
    double litFraction() const;
    // The camera's noise, σ of one frame in samples, from the latest accepted Gray pair (the
    // median absolute residual of pattern + inverse − white − black); 0 before one.
    double noiseSigma() const { return noiseSigma_; }

private:
    // Each stores what the group's acceptance keeps (candidate*, pendingSigma_).
    FrameVerdict checkLit(const std::vector<float>& white, const std::vector<float>& black);
    FrameVerdict checkBimodal(const std::vector<float>& image) const;
    FrameVerdict checkPair(const std::vector<float>& pattern, const std::vector<float>& inverse);
    FrameVerdict checkChanged(const std::vector<float>& image) const;
    void accept(const std::vector<std::size_t>& group);

    const proto::StructuredLightSequence& sequence_;
    FrameCheckSettings settings_;
    std::vector<std::vector<std::size_t>> groups_;
    std::vector<std::size_t> groupOf_;  // pattern index → group index
    int width_ = 0, height_ = 0;
    double maxValue_ = 255;
    // The current group's captures (pattern index, samples as floats).
    std::vector<std::pair<std::size_t, std::vector<float>>> pending_;
    std::vector<float> white_, black_, previous_;
    std::vector<std::uint32_t> lit_;  // indices of the lit pixels
    std::vector<float> candidateWhite_, candidateBlack_;
    std::vector<std::uint32_t> candidateLit_;
    double pendingSigma_ = 0;
    double noiseSigma_ = 0;
};

}  // namespace vpe::firmware
