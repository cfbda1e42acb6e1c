// SPDX-License-Identifier: MIT
// ScanFrameCheck: the statistics over the lit pixels that tell a capture of the right pattern
// from a stale one.
#include "vpe/firmware/scan/frame_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "frame_measures.h"

namespace vpe::firmware {

using frame_measures::percent;

namespace frame_measures {

std::string percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
    return text;
}

std::vector<std::uint32_t> litPixels(std::span<const float> white, std::span<const float> black,
                                     float floor) {
    std::vector<std::uint32_t> lit;
    for (std::size_t p = 0; p < white.size(); ++p) {
        if (white[p] - black[p] >= floor) {
            lit.push_back(static_cast<std::uint32_t>(p));
        }
    }
    return lit;
}

FrameVerdict litVerdict(std::size_t lit, std::size_t pixels, const FrameCheckSettings& settings) {
    const double fraction =
        pixels > 0 ? static_cast<double>(lit) / static_cast<double>(pixels) : 0.0;
    if (lit == 0 || fraction < settings.minLitFraction) {
        return {FrameProblem::kNotLit,
                "white − black reaches " + percent(settings.minContrast) + " of full scale on " +
                    percent(fraction) + " of the camera's pixels (needs " +
                    percent(settings.minLitFraction) +
                    "): white or black was captured before the projector showed it, or the "
                    "projector's light does not reach the camera"};
    }
    return {};
}

FrameVerdict changedVerdict(double changed, const std::string& what) {
    if (changed < kMinChangedFraction) {
        return {FrameProblem::kUnchanged,
                "only " + percent(changed) + " of the lit pixels changed since the previous " +
                    "capture (" + what + " changes at least " + percent(kMinChangedFraction) +
                    "): captured before the projector showed it"};
    }
    return {};
}

}  // namespace frame_measures

namespace {

// A Gray pattern's pixel is "between" black and white when (v − black) / (white − black) lies
// in this band: a capture made while the projector switched blends two patterns there.
constexpr double kBimodalLow = 0.25, kBimodalHigh = 0.75;
// A pixel disagrees with pattern + inverse = white + black when the residual exceeds this share
// of its white − black: a stale capture leaves the whole of it, a blend half, noise and the
// camera's response at stripe edges less.
constexpr float kPairResidual = 0.4f;
// σ of a normal distribution from the median absolute deviation.
constexpr double kMadToSigma = 1.4826;

std::vector<float> floatsOf(const CameraImage& image) {
    return std::vector<float>(image.samples.begin(), image.samples.end());
}

bool isInverseOf(const proto::PatternSpec& inverse, const proto::PatternSpec& pattern) {
    return pattern.kind == proto::PatternKind::kGray && !pattern.inverted &&
           inverse.kind == proto::PatternKind::kGray && inverse.inverted &&
           inverse.axis == pattern.axis && inverse.bit == pattern.bit;
}

}  // namespace

const char* frameProblemName(FrameProblem problem) {
    switch (problem) {
        case FrameProblem::kNone:
            return "";
        case FrameProblem::kNotLit:
            return "not_lit";
        case FrameProblem::kNotBimodal:
            return "not_bimodal";
        case FrameProblem::kPairMismatch:
            return "pair_mismatch";
        case FrameProblem::kUnchanged:
            return "unchanged";
    }
    return "";
}

ScanFrameCheck::ScanFrameCheck(const proto::StructuredLightSequence& sequence,
                               const FrameCheckSettings& settings)
    : sequence_(sequence), settings_(settings) {
    const std::vector<proto::PatternSpec>& patterns = sequence.patterns();
    groupOf_.assign(patterns.size(), 0);
    for (std::size_t i = 0; i < patterns.size();) {
        std::vector<std::size_t> group{i};
        if (i + 1 < patterns.size() && ((patterns[i].kind == proto::PatternKind::kWhite &&
                                         patterns[i + 1].kind == proto::PatternKind::kBlack) ||
                                        isInverseOf(patterns[i + 1], patterns[i]))) {
            group.push_back(i + 1);
        }
        for (const std::size_t index : group) {
            groupOf_[index] = groups_.size();
        }
        i += group.size();
        groups_.push_back(std::move(group));
    }
}

double ScanFrameCheck::litFraction() const {
    const auto pixels = static_cast<double>(width_) * static_cast<double>(height_);
    return pixels > 0 ? static_cast<double>(lit_.size()) / pixels : 0.0;
}

FrameVerdict ScanFrameCheck::check(std::size_t index, const CameraImage& image) {
    if (index >= groupOf_.size()) {
        throw std::invalid_argument("scan frame check: pattern " + std::to_string(index) +
                                    " is not in the sequence");
    }
    if (image.channels != 1 || image.samples.size() != image.pixelCount() ||
        image.pixelCount() == 0) {
        throw std::invalid_argument(
            "scan frame check: an image's samples are not its size (one channel)");
    }
    if (width_ == 0) {
        width_ = image.width;
        height_ = image.height;
        maxValue_ = image.maxValue;
    } else if (image.width != width_ || image.height != height_ || image.maxValue != maxValue_) {
        throw std::invalid_argument("scan frame check: the captures differ in size or depth");
    }
    const std::vector<std::size_t>& group = groups_[groupOf_[index]];
    if (index == group.front()) {
        pending_.clear();
    }
    std::vector<float> values = floatsOf(image);
    const proto::PatternSpec& pattern = sequence_.patterns()[index];
    FrameVerdict verdict;
    switch (pattern.kind) {
        case proto::PatternKind::kWhite:
            break;
        case proto::PatternKind::kBlack:
            if (!pending_.empty() &&
                sequence_.patterns()[pending_.back().first].kind == proto::PatternKind::kWhite) {
                verdict = checkLit(pending_.back().second, values);
            }
            break;
        case proto::PatternKind::kGray:
            verdict = checkBimodal(values);
            if (verdict.passed() && pattern.inverted && !pending_.empty() &&
                isInverseOf(pattern, sequence_.patterns()[pending_.back().first])) {
                verdict = checkPair(pending_.back().second, values);
            }
            break;
        case proto::PatternKind::kPhase:
            verdict = checkChanged(values);
            break;
    }
    if (verdict.passed()) {
        pending_.emplace_back(index, std::move(values));
        if (index == group.back()) {
            accept(group);
        }
    }
    return verdict;
}

FrameVerdict ScanFrameCheck::checkLit(const std::vector<float>& white,
                                      const std::vector<float>& black) {
    std::vector<std::uint32_t> lit = frame_measures::litPixels(
        white, black, static_cast<float>(settings_.minContrast * maxValue_));
    if (FrameVerdict verdict = frame_measures::litVerdict(lit.size(), white.size(), settings_);
        !verdict.passed()) {
        return verdict;
    }
    candidateLit_ = std::move(lit);
    candidateWhite_ = white;
    candidateBlack_ = black;
    return {};
}

FrameVerdict ScanFrameCheck::checkBimodal(const std::vector<float>& image) const {
    if (lit_.empty()) {
        return {};
    }
    std::size_t between = 0;
    for (const std::uint32_t p : lit_) {
        const double n = (image[p] - black_[p]) / (white_[p] - black_[p]);
        between += n > kBimodalLow && n < kBimodalHigh ? 1 : 0;
    }
    const double fraction = static_cast<double>(between) / static_cast<double>(lit_.size());
    if (fraction > settings_.tolerance) {
        return {FrameProblem::kNotBimodal,
                percent(fraction) + " of the lit pixels lie between black and white (at most " +
                    percent(settings_.tolerance) +
                    "): captured while the projector switched, or the stripes are blurred "
                    "(focus the projector, or raise scan.phase_period)"};
    }
    return {};
}

FrameVerdict ScanFrameCheck::checkPair(const std::vector<float>& pattern,
                                       const std::vector<float>& inverse) {
    if (lit_.empty()) {
        return {};
    }
    std::size_t disagree = 0;
    std::vector<float> residuals;
    residuals.reserve(lit_.size());
    for (const std::uint32_t p : lit_) {
        const float contrast = white_[p] - black_[p];
        const float residual = std::abs(pattern[p] + inverse[p] - white_[p] - black_[p]);
        disagree += residual > kPairResidual * contrast ? 1 : 0;
        residuals.push_back(residual);
    }
    const double fraction = static_cast<double>(disagree) / static_cast<double>(lit_.size());
    if (fraction > settings_.tolerance) {
        return {FrameProblem::kPairMismatch,
                "pattern + inverse differ from white + black on " + percent(fraction) +
                    " of the lit pixels (at most " + percent(settings_.tolerance) +
                    "): one of the two was captured before the projector showed it"};
    }
    // Four frames' noise adds up in the residual: σ(residual) = 2σ.
    const auto middle = residuals.begin() + static_cast<std::ptrdiff_t>(residuals.size() / 2);
    std::nth_element(residuals.begin(), middle, residuals.end());
    pendingSigma_ = kMadToSigma * static_cast<double>(*middle) / 2.0;
    return {};
}

FrameVerdict ScanFrameCheck::checkChanged(const std::vector<float>& image) const {
    if (lit_.empty() || previous_.empty()) {
        return {};
    }
    const double changed = frame_measures::changedShare<float>(
        image, previous_, 1, lit_, frame_measures::changeThreshold(noiseSigma_));
    return frame_measures::changedVerdict(changed, "a new phase step");
}

void ScanFrameCheck::accept(const std::vector<std::size_t>& group) {
    const proto::PatternSpec& first = sequence_.patterns()[group.front()];
    if (first.kind == proto::PatternKind::kWhite && group.size() == 2) {
        white_ = std::move(candidateWhite_);
        black_ = std::move(candidateBlack_);
        lit_ = std::move(candidateLit_);
    } else if (first.kind == proto::PatternKind::kGray && group.size() == 2) {
        noiseSigma_ = pendingSigma_;
    }
    previous_ = pending_.back().second;
    pending_.clear();
}

}  // namespace vpe::firmware
