// SPDX-License-Identifier: MIT
// StructuredLightSequence: the patterns a projector shows to be scanned — white, black, Gray
// code with inverses and phase shifting, on both axes — defined once for the device that shows
// them (vpe-player --scan), the simulator that renders them and the decoder (vpe scan,
// vpe calibrate) that reads them back (proto/SCAN.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/proto/input_error.h"

namespace vpe::proto {

enum class PatternKind : std::uint8_t {
    kWhite,  // every pixel at level 1
    kBlack,  // every pixel at level 0
    kGray,   // one bit of the Gray code of the column (or row) index, or its inverse
    kPhase,  // one step of a sinusoid along the columns (or rows)
};

// Which projector coordinate a Gray or phase pattern encodes.
enum class PatternAxis : std::uint8_t {
    kColumns,  // x: the pattern varies along a row
    kRows,     // y: the pattern varies along a column
};

struct PatternSpec {
    PatternKind kind = PatternKind::kWhite;
    PatternAxis axis = PatternAxis::kColumns;
    int bit = 0;            // kGray: bit of the Gray code (0 = least significant)
    bool inverted = false;  // kGray: 1 where the bit is 0
    int step = 0;           // kPhase: s of N, the sinusoid shifted by 2π·s/N

    // The pattern's name in manifests and file names: "white", "black", "gray-x-b10",
    // "gray-x-b10-inv", "phase-y-s3".
    std::string name() const;
};

struct StructuredLightParameters {
    int width = 0, height = 0;  // the projector's pixels
    // Pixels per period of the sinusoid: a power of two, 8..1024. The Gray code stops at the
    // bit that splits a period in quarters: finer stripes are what defocus blurs first, and the
    // phase measures inside a period better than they would.
    int phasePeriod = 32;
    // N, 3..64: harmonics of the projector's response up to N − 2 cancel. 0: no phase images
    // (a Gray code alone, as other tools show it; the period is then unused).
    int phaseSteps = 8;
    // Projector pixels per code, along both axes (OpenCV's GrayCodePattern step): the Gray
    // code counts ⌊x / codeStep⌋, so the projector's size and the code's depth stay apart.
    int codeStep = 1;
    // The least significant Gray bit shown. Absent: log2(period) − 2 with the phase (a Gray bin
    // is a quarter period), 0 without it (every bit).
    std::optional<int> lowestGrayBit = std::nullopt;
    // White and black shown. Other tools may leave them out; the decoder then takes each Gray
    // pair's mean and range instead.
    bool flatFields = true;
};

// One line naming the problem, for parameters or manifests that cannot describe a scan.
class StructuredLightError : public InputError {
public:
    using InputError::InputError;
};

// Pixel centres are at integer coordinates: column x covers [x − ½, x + ½). A Gray pattern
// lights column x when bit `bit` of gray(⌊x / codeStep⌋) is 1 (0 when inverted). Phase step s
// lights column x at level ½ + ½·cos(2π·x/T − 2π·s/N). Rows likewise with y. Levels are drive
// levels (what the frame buffer holds), shown as 8-bit codes round(255·level) on all three
// channels.
//
// The order patterns() lists (the device shows them in it; a manifest may list its images in
// any): white and black when shown, then per axis (columns, then rows) the Gray bits from the
// most significant down to lowestGrayBit(), each followed by its inverse, then the N phase steps.
class StructuredLightSequence {
public:
    // Throws StructuredLightError for a size outside 8..16384; a code step that leaves fewer
    // than 2 codes along an axis; N other than 0 or 3..64; with a phase, a period that is not a
    // power of two in 8..1024 or longer than the axis, or Gray bins wider than a quarter period
    // (the phase could not be unwrapped); a lowest Gray bit that leaves an axis without bits.
    explicit StructuredLightSequence(const StructuredLightParameters& parameters);

    const StructuredLightParameters& parameters() const { return parameters_; }
    const std::vector<PatternSpec>& patterns() const { return patterns_; }
    // The index of the pattern with this name, or −1.
    int find(std::string_view name) const;

    bool hasPhase() const { return parameters_.phaseSteps > 0; }
    // Bits of the Gray code that cover the axis: ceil(log2(codes)), codes = ceil(extent / step).
    int grayBits(PatternAxis axis) const;
    // The least significant bit shown (StructuredLightParameters::lowestGrayBit, resolved).
    int lowestGrayBit() const { return lowestGrayBit_; }
    // Projector pixels that the shown Gray bits cannot tell apart: codeStep · 2^lowestGrayBit.
    int grayBinWidth() const { return parameters_.codeStep << lowestGrayBit_; }

    double level(const PatternSpec& pattern, int x, int y) const;
    std::uint8_t code(const PatternSpec& pattern, int x, int y) const;
    // The pattern as the projector shows it: width × height 8-bit codes, rows from the top.
    void render(const PatternSpec& pattern, std::span<std::uint8_t> codes) const;

private:
    StructuredLightParameters parameters_;
    int lowestGrayBit_ = 0;
    std::vector<PatternSpec> patterns_;
};

// The reflected binary code and its inverse.
constexpr std::uint32_t grayEncode(std::uint32_t value) {
    return value ^ (value >> 1);
}
constexpr std::uint32_t grayDecode(std::uint32_t gray) {
    for (std::uint32_t shift = 1; shift < 32; shift <<= 1) {
        gray ^= gray >> shift;
    }
    return gray;
}

}  // namespace vpe::proto
