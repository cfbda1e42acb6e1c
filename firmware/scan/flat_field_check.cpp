// SPDX-License-Identifier: MIT
// FlatFieldCheck: the capture order that makes consecutive flat fields differ, and the lit and
// changed measures of the scan's check on colour captures.
#include "vpe/firmware/scan/flat_field_check.h"

#include <stdexcept>
#include <string>

#include "vpe/proto/luminance.h"

#include "frame_measures.h"

namespace vpe::firmware {

namespace {

std::vector<float> luminanceOf(const CameraImage& image) {
    std::vector<float> values(image.pixelCount());
    for (std::size_t p = 0; p < values.size(); ++p) {
        // Rec. 709 luminance, as the offline readers reduce colour scans (proto/SCAN.md).
        values[p] = proto::luminance709f(image.samples[3 * p], image.samples[3 * p + 1],
                                         image.samples[3 * p + 2]);
    }
    return values;
}

// `indices` (one ladder, lowest first) alternating between its lower and upper half: a, a+h,
// a+1, a+h+1, … with h = ⌈n/2⌉, so that two consecutive entries are at least h − 1 apart.
std::vector<std::size_t> alternatingHalves(const std::vector<std::size_t>& indices) {
    const std::size_t half = (indices.size() + 1) / 2;
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < half; ++k) {
        order.push_back(indices[k]);
        if (k + half < indices.size()) {
            order.push_back(indices[k + half]);
        }
    }
    return order;
}

// Exposure stops 0, n−1, 1, n−2, …: long and short alternate.
std::vector<std::size_t> alternatingEnds(const std::vector<std::size_t>& indices) {
    std::vector<std::size_t> order;
    for (std::size_t low = 0, high = indices.size(); low < high;) {
        order.push_back(indices[low++]);
        if (low < high) {
            order.push_back(indices[--high]);
        }
    }
    return order;
}

}  // namespace

FlatFieldCheck::FlatFieldCheck(std::vector<proto::FlatField> fields,
                               const FrameCheckSettings& settings, double noiseSigma)
    : fields_(std::move(fields)),
      settings_(settings),
      threshold_(frame_measures::changeThreshold(noiseSigma)) {
    if (fields_.size() < 2 || fields_[0].kind != proto::FlatFieldKind::kBlack ||
        fields_[1].kind != proto::FlatFieldKind::kWhite) {
        throw std::invalid_argument("flat field check: the sequence must start with black, white");
    }
    groups_.push_back({0, 1});
    std::vector<std::size_t> ramps;
    for (int channel = 0; channel < 3; ++channel) {
        std::vector<std::size_t> ladder;
        for (std::size_t i = 2; i < fields_.size(); ++i) {
            if (fields_[i].kind == proto::FlatFieldKind::kPrimary &&
                fields_[i].channel == channel) {
                ladder.push_back(i);
            }
        }
        for (const std::size_t index : alternatingHalves(ladder)) {
            groups_.push_back({index});
        }
    }
    for (std::size_t i = 2; i < fields_.size(); ++i) {
        if (fields_[i].kind == proto::FlatFieldKind::kRamp) {
            ramps.push_back(i);
        }
    }
    for (const std::size_t index : alternatingEnds(ramps)) {
        groups_.push_back({index});
    }
    groupOf_.assign(fields_.size(), fields_.size());
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        for (const std::size_t index : groups_[g]) {
            groupOf_[index] = g;
        }
    }
    for (std::size_t i = 0; i < fields_.size(); ++i) {
        if (groupOf_[i] == fields_.size()) {
            throw std::invalid_argument("flat field check: " + fields_[i].name() +
                                        " appears twice or out of place in the sequence");
        }
    }
}

double FlatFieldCheck::litFraction() const {
    const auto pixels = static_cast<double>(width_) * static_cast<double>(height_);
    return pixels > 0 ? static_cast<double>(lit_.size()) / pixels : 0.0;
}

FrameVerdict FlatFieldCheck::check(std::size_t index, const CameraImage& image) {
    if (index >= fields_.size()) {
        throw std::invalid_argument("flat field check: field " + std::to_string(index) +
                                    " is not in the sequence");
    }
    if (image.channels != 3 || image.samples.size() != image.sampleCount() ||
        image.pixelCount() == 0) {
        throw std::invalid_argument(
            "flat field check: an image's samples are not its size (three channels)");
    }
    if (width_ == 0) {
        width_ = image.width;
        height_ = image.height;
        maxValue_ = image.maxValue;
    } else if (image.width != width_ || image.height != height_ || image.maxValue != maxValue_) {
        throw std::invalid_argument("flat field check: the captures differ in size or depth");
    }
    const std::vector<std::size_t>& group = groups_[groupOf_[index]];
    if (index == group.front()) {
        pending_.clear();
    }
    FrameVerdict verdict;
    switch (fields_[index].kind) {
        case proto::FlatFieldKind::kBlack:
            break;
        case proto::FlatFieldKind::kWhite:
            if (!pending_.empty() &&
                fields_[pending_.back().first].kind == proto::FlatFieldKind::kBlack) {
                const std::vector<float> white = luminanceOf(image);
                const std::vector<float> black = luminanceOf(pending_.back().second);
                candidateLit_ = frame_measures::litPixels(
                    white, black, static_cast<float>(settings_.minContrast * maxValue_));
                verdict = frame_measures::litVerdict(candidateLit_.size(), white.size(), settings_);
            }
            break;
        case proto::FlatFieldKind::kPrimary:
        case proto::FlatFieldKind::kRamp:
            if (!lit_.empty() && !previous_.empty()) {
                const double changed = frame_measures::changedShare<std::uint16_t>(
                    image.samples, previous_, 3, lit_, threshold_);
                verdict = frame_measures::changedVerdict(changed, "a flat field after another");
            }
            break;
    }
    if (verdict.passed()) {
        pending_.emplace_back(index, image);
        if (index == group.back()) {
            if (fields_[group.front()].kind == proto::FlatFieldKind::kBlack && group.size() == 2) {
                lit_ = std::move(candidateLit_);
            }
            previous_ = std::move(pending_.back().second.samples);
            pending_.clear();
        }
    }
    return verdict;
}

}  // namespace vpe::firmware
