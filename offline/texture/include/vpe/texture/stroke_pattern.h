// SPDX-License-Identifier: MIT
// Hidasuki strokes for weight maps: long, thin, gently curving bands with soft edges that
// cross each other, like the red-brown marks straw leaves on Bizen ware. Seeded; widths,
// coverage and spread may come from a source's own label map. docs/compose.md defines every
// parameter.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "vpe/texture/streak_statistics.h"

namespace vpe::texture {

// Which axes the map continues across (the texture wraps around the vase in u).
enum class StrokeWrap { kNone, kU, kUV };

// As written in a `strokes:` entry; unset values take defaults, some of them measured from
// the label map `labels` (region `region`) when one is given.
struct StrokeParameters {
    std::optional<double> coverage;  // share of the map with weight ≥ ½
    std::optional<int> count;        // or this many strokes
    std::optional<double> width;     // median full width of a stroke's body, texels
    std::optional<double> spread;    // σ of ln(width) between strokes
    double wobble = 0.15;            // σ of ln(width) along one stroke
    std::optional<double> length;    // mean length, texels (lengths uniform in ½..1½ of it)
    double bend = 15;                // σ of the heading's wander along a stroke, degrees
    std::optional<double> softness;  // width of the edge ramp (weight 1 → 0), texels
    double angleDegrees = 0;         // mean heading, counter-clockwise from the x axis
    double angleSpread = 180;        // headings uniform in angle ± spread / 2, degrees
    std::uint64_t seed = 1;
    StrokeWrap wrap = StrokeWrap::kU;
    std::filesystem::path labels;  // `from=`: a label image (vpe segment's labels.png)
    std::optional<int> region;     // the label whose streaks to measure
};

// Every value decided, and where the measured ones came from.
struct ResolvedStrokes {
    double coverage = 0;  // 0 when `count` rules
    int count = 0;        // 0 when `coverage` rules
    double width = 0;
    double spread = 0;
    double wobble = 0;
    double length = 0;
    double bend = 0;
    double softness = 0;
    double angleDegrees = 0;
    double angleSpread = 0;
    std::uint64_t seed = 1;
    StrokeWrap wrap = StrokeWrap::kU;
    std::optional<StreakStatistics> source;  // the label map's streaks, when `from=` was given
    // Width and spread defaulted from `source`: generateStrokes fits the strokes' body width
    // and spread so that the drawn map's streaks measure like the source's.
    bool fitWidth = false;
    bool fitSpread = false;
};

// Fills the defaults: coverage 0.25 (or the source's), width 12 texels (or the source's
// median width), spread 0.25 (or the source's log spread), length 32 widths, softness 0.4
// widths. Reads and measures the label map; throws InputError naming it.
ResolvedStrokes resolveStrokes(const StrokeParameters& parameters);

struct StrokePattern {
    std::vector<float> weight;  // [y * width + x], in [0, 1]
    int strokes = 0;
    double coverage = 0;   // share of pixels with weight ≥ ½
    double bodyWidth = 0;  // the width and spread drawn with (fitted, when defaulted
    double spread = 0;     // from a source)
    int fitRounds = 0;     // patterns drawn to fit them (0: none)
};

// Draws strokes until `count` are drawn or the covered share is as near `coverage` as one
// more stroke can bring it; strokes falling wholly beyond an edge that does not wrap are not
// counted. Crossings and the rounded ends make a map's measured widths
// differ from its strokes' body widths, so when the width or spread come from a source, the
// map is redrawn (same strokes, up to 4 times) with the body width scaled by source median /
// measured median and the spread moved by source spread − measured spread, keeping the
// closest. Deterministic for a seed, whatever the machine's thread count.
StrokePattern generateStrokes(const ResolvedStrokes& strokes, int width, int height);

}  // namespace vpe::texture
