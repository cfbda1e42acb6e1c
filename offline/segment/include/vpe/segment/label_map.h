// SPDX-License-Identifier: MIT
// LabelMap: a material label per pixel, and what is done to one after clustering: seeded
// labelling, removing tiny islands, a deterministic label order, and the files written for
// the next stages and for people (labels.png, labels-overlay.png).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/segment/average_appearance.h"

namespace vpe::segment {

struct LabelMap {
    // The value of pixels without a valid model (and so without a label): labels are
    // 0..254, so 8-bit label files hold up to 255 labels.
    static constexpr std::uint8_t kNoLabel = 255;
    static constexpr int kMaxLabels = 255;

    int width = 0;
    int height = 0;
    int labels = 0;                    // labels are 0..labels − 1
    std::vector<std::uint8_t> values;  // [y][x]
};

struct PixelSeed {
    int x = 0;
    int y = 0;
};

// What seeded labelling compares pixels in.
enum class SeedSpace {
    // The paper's method: the average colour in CIELAB (ΔE76). CIELAB, not linear RGB:
    // differences between dark materials count as much as those between light ones, as people
    // (and the paper's user, picking seeds on the average image) see them.
    kColour,
    // vpe's default: the clustering features (colour and the coefficients' principal
    // components), so materials of one colour that differ in gloss are told apart too.
    kAppearance,
};

// Seeded segmentation: label i goes to every pixel nearer, in `space`, to seed i (the mean
// of a 5 × 5 window around it) than to any other seed. Seeds must be on valid pixels
// (checked by the caller).
LabelMap labelBySeeds(const Appearance& appearance, const std::vector<PixelSeed>& seeds,
                      SeedSpace space);

// Connected regions (4-connectivity) smaller than minArea pixels take the label that borders
// them most (ties: the lower label), smallest regions first, until none is left that has a
// neighbour. Returns how many regions were merged. Labels may disappear; they keep their
// numbers (see compactLabels).
std::size_t removeIslands(LabelMap& map, std::size_t minArea);

// Renumbers the labels in use by increasing mean luminance (Y) of their average colour, so a
// segmentation reads the same whatever order clustering found them in.
void orderLabelsByLuminance(LabelMap& map, const Appearance& appearance);

// Pixels per label.
std::vector<std::size_t> labelAreas(const LabelMap& map);

// Reads a label image: 8-bit, value = label, 255 = unlabelled; one channel, or grey saved as
// RGB(A). Throws InputError naming the file (and pixel) when it is not one.
LabelMap readLabelImage(const std::filesystem::path& path);
// The same, and it must be width × height (the model it labels).
LabelMap readLabelImage(const std::filesystem::path& path, int width, int height);

// Writes the label values as an 8-bit one-channel image, atomically.
void writeLabelImage(const std::filesystem::path& path, const LabelMap& map);

// The average image for people: sRGB, exposed so its brightest 1% saturate.
std::vector<std::uint8_t> averagePicture(const Appearance& appearance);

// The average image with each label's colour blended in and the boundaries between labels
// drawn white, written atomically.
void writeLabelOverlay(const std::filesystem::path& path, const LabelMap& map,
                       const Appearance& appearance);

// The overlay's path next to a label file: labels.png → labels-overlay.png.
std::filesystem::path overlayPathFor(const std::filesystem::path& labels);

}  // namespace vpe::segment
