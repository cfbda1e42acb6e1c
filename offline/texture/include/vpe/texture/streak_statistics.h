// SPDX-License-Identifier: MIT
// Streak statistics of a two-valued pattern: the share of the map its streaks cover and the
// distribution of their widths along the medial axis. One definition, applied alike to a
// source's label map and to a generated or composed weight map, so the two compare.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace vpe::segment {
struct LabelMap;
}

namespace vpe::texture {

// What a pixel of the pattern is.
enum class StreakPixel : std::uint8_t { kBackground = 0, kStreak = 1, kUnknown = 2 };

struct StreakMask {
    int width = 0;
    int height = 0;
    std::vector<StreakPixel> pixels;  // [y * width + x]
    // The map continues across x = 0 | width (a texture wrapped around the vase): widths are
    // measured across that seam instead of stopping at it.
    bool wrapsU = false;
};

// Every figure is NaN when undefined (nothing known, no medial-axis pixel trusted).
struct StreakStatistics {
    std::size_t knownPixels = 0;   // streak + background
    std::size_t streakPixels = 0;  //
    double coverage = 0;           // streakPixels / knownPixels
    // Full widths in texels, one per measured streak pixel (see measureStreaks).
    std::vector<float> widths;
    double widthQuartile1 = 0;
    double widthMedian = 0;
    double widthQuartile3 = 0;
    double widthMean = 0;
    // Spread of the widths as the σ of a log-normal with these quartiles: ln(Q3/Q1) / 1.349.
    double widthLogSpread = 0;
};

// Widths are local thickness over the medial axis. The medial axis is the ridge of the exact
// Euclidean distance transform D (from a streak pixel's centre to the nearest background
// pixel's centre): pixels whose D is a local maximum across the band along one of the four
// pixel axes (≥ both neighbours, > one). Its full width there is 2D − 1 for a strict maximum
// (an odd number of pixels across) and 2D when a neighbour across ties (an even number: the
// centre line falls between the two), so a band n pixels across measures n. Every streak
// pixel then takes the width of the widest medial disc (centre c, radius D(c)) holding it, so
// the distribution is per pixel (area-weighted) and spurs of a ragged edge do not count. A
// pixel is measured only when that disc is trusted: its centre's nearest background pixel is
// nearer than every unknown pixel and the map's edges (else the band may go on unseen).
StreakStatistics measureStreaks(const StreakMask& mask);

// Region `region` of a label map as streaks, every other label background, unlabelled pixels
// (segment::LabelMap::kNoLabel) unknown.
StreakMask streakMaskFromLabels(const segment::LabelMap& labels, int region);

// A weight map as streaks where weight ≥ threshold (½: the weight's own midpoint).
StreakMask streakMaskFromWeights(const std::vector<float>& weight, int width, int height,
                                 bool wrapsU, float threshold = 0.5f);

// Reads a label image and measures one of its regions. Throws InputError naming the file when
// it is not a label image or `region` is not one of its labels.
StreakStatistics measureLabelStreaks(const std::filesystem::path& labels, int region);

}  // namespace vpe::texture
