// SPDX-License-Identifier: MIT
// The structured-light sequence: names, order and levels.
#include "vpe/proto/structured_light.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace vpe::proto {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMinExtent = 8;
constexpr int kMaxExtent = 16384;

const char* axisLetter(PatternAxis axis) {
    return axis == PatternAxis::kColumns ? "x" : "y";
}

}  // namespace

std::string PatternSpec::name() const {
    switch (kind) {
        case PatternKind::kWhite:
            return "white";
        case PatternKind::kBlack:
            return "black";
        case PatternKind::kGray:
            return std::string("gray-") + axisLetter(axis) + "-b" + std::to_string(bit) +
                   (inverted ? "-inv" : "");
        case PatternKind::kPhase:
            return std::string("phase-") + axisLetter(axis) + "-s" + std::to_string(step);
    }
    return "unknown";
}

StructuredLightSequence::StructuredLightSequence(const StructuredLightParameters& p)
    : parameters_(p) {
    if (p.width < kMinExtent || p.width > kMaxExtent || p.height < kMinExtent ||
        p.height > kMaxExtent) {
        throw StructuredLightError("projector size " + std::to_string(p.width) + "x" +
                                   std::to_string(p.height) + " is outside 8..16384");
    }
    const int shorter = std::min(p.width, p.height);
    if (p.codeStep < 1 || p.codeStep > shorter / 2) {
        throw StructuredLightError("code step " + std::to_string(p.codeStep) + " outside 1.." +
                                   std::to_string(shorter / 2) + " (2 codes across the " +
                                   std::to_string(shorter) + " pixels of the shorter axis)");
    }
    if (p.phaseSteps != 0 && (p.phaseSteps < 3 || p.phaseSteps > 64)) {
        throw StructuredLightError("phase steps " + std::to_string(p.phaseSteps) +
                                   " outside 3..64 (0: no phase images)");
    }
    if (hasPhase()) {
        if (p.phasePeriod < 8 || p.phasePeriod > 1024 ||
            !std::has_single_bit(static_cast<unsigned>(p.phasePeriod))) {
            throw StructuredLightError("phase period " + std::to_string(p.phasePeriod) +
                                       " is not a power of two in 8..1024");
        }
        if (p.phasePeriod > shorter) {
            throw StructuredLightError("phase period " + std::to_string(p.phasePeriod) +
                                       " is longer than the projector's " +
                                       std::to_string(shorter) + " pixels");
        }
    }
    const int bits = std::min(grayBits(PatternAxis::kColumns), grayBits(PatternAxis::kRows));
    lowestGrayBit_ = p.lowestGrayBit.value_or(
        hasPhase() ? std::countr_zero(static_cast<unsigned>(p.phasePeriod)) - 2 : 0);
    if (lowestGrayBit_ < 0 || lowestGrayBit_ >= bits) {
        throw StructuredLightError("lowest Gray bit " + std::to_string(lowestGrayBit_) +
                                   " outside 0.." + std::to_string(bits - 1) +
                                   " (the bits of the shorter axis' code)");
    }
    // The phase is unwrapped by the Gray bin: a bin read one off must stay within half a period.
    if (hasPhase() && 4 * grayBinWidth() > p.phasePeriod) {
        throw StructuredLightError(
            "Gray bins of " + std::to_string(grayBinWidth()) + " pixels (code step " +
            std::to_string(p.codeStep) + ", lowest bit " + std::to_string(lowestGrayBit_) +
            ") are wider than a quarter of the phase period " + std::to_string(p.phasePeriod));
    }
    if (p.flatFields) {
        patterns_.push_back({PatternKind::kWhite});
        patterns_.push_back({PatternKind::kBlack});
    }
    for (const PatternAxis axis : {PatternAxis::kColumns, PatternAxis::kRows}) {
        for (int bit = grayBits(axis) - 1; bit >= lowestGrayBit_; --bit) {
            patterns_.push_back({PatternKind::kGray, axis, bit, false, 0});
            patterns_.push_back({PatternKind::kGray, axis, bit, true, 0});
        }
        for (int step = 0; step < p.phaseSteps; ++step) {
            patterns_.push_back({PatternKind::kPhase, axis, 0, false, step});
        }
    }
}

int StructuredLightSequence::find(std::string_view name) const {
    for (std::size_t i = 0; i < patterns_.size(); ++i) {
        if (patterns_[i].name() == name) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

int StructuredLightSequence::grayBits(PatternAxis axis) const {
    const int extent = axis == PatternAxis::kColumns ? parameters_.width : parameters_.height;
    const int codes = (extent + parameters_.codeStep - 1) / parameters_.codeStep;
    return static_cast<int>(std::bit_width(static_cast<unsigned>(codes - 1)));
}

double StructuredLightSequence::level(const PatternSpec& pattern, int x, int y) const {
    const int coordinate = pattern.axis == PatternAxis::kColumns ? x : y;
    switch (pattern.kind) {
        case PatternKind::kWhite:
            return 1.0;
        case PatternKind::kBlack:
            return 0.0;
        case PatternKind::kGray: {
            const auto code = static_cast<std::uint32_t>(coordinate / parameters_.codeStep);
            const bool lit = (grayEncode(code) >> pattern.bit) & 1u;
            return lit != pattern.inverted ? 1.0 : 0.0;
        }
        case PatternKind::kPhase: {
            const double angle = 2 * kPi *
                                 (static_cast<double>(coordinate) / parameters_.phasePeriod -
                                  static_cast<double>(pattern.step) / parameters_.phaseSteps);
            return 0.5 + 0.5 * std::cos(angle);
        }
    }
    return 0.0;
}

std::uint8_t StructuredLightSequence::code(const PatternSpec& pattern, int x, int y) const {
    return static_cast<std::uint8_t>(std::lround(255.0 * level(pattern, x, y)));
}

void StructuredLightSequence::render(const PatternSpec& pattern,
                                     std::span<std::uint8_t> codes) const {
    const int width = parameters_.width, height = parameters_.height;
    if (codes.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {
        throw StructuredLightError("pattern buffer holds " + std::to_string(codes.size()) +
                                   " codes, not " + std::to_string(width) + "x" +
                                   std::to_string(height));
    }
    // Every pattern varies along one axis only: compute one line of codes, then copy it.
    if (pattern.axis == PatternAxis::kColumns || pattern.kind == PatternKind::kWhite ||
        pattern.kind == PatternKind::kBlack) {
        std::vector<std::uint8_t> row(static_cast<std::size_t>(width));
        for (int x = 0; x < width; ++x) {
            row[static_cast<std::size_t>(x)] = code(pattern, x, 0);
        }
        for (int y = 0; y < height; ++y) {
            std::copy(row.begin(), row.end(),
                      codes.begin() + static_cast<std::ptrdiff_t>(y) * width);
        }
        return;
    }
    for (int y = 0; y < height; ++y) {
        const std::uint8_t value = code(pattern, 0, y);
        std::fill_n(codes.begin() + static_cast<std::ptrdiff_t>(y) * width, width, value);
    }
}

}  // namespace vpe::proto
