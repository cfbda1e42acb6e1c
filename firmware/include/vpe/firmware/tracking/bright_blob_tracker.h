// SPDX-License-Identifier: MIT
// BrightBlobTracker: finds the hand-held lamp in a luminance frame as the brightest blob. With
// the camera's exposure fixed short, the lamp is a saturated spot on a dark room; everything
// else (a lit face, a glint on the object) is dimmer or smaller.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "vpe/firmware/tracking/luminance_frame.h"

namespace vpe::firmware {

struct BlobTrackerConfig {
    // Pixels at or above this level (1–255) belong to blobs.
    int threshold = 200;
    // In [0, 1): when positive, the level is raised to this fraction of the frame's brightest
    // pixel, so a lamp brighter than expected keeps a compact core. 0: the absolute level only.
    double relativeThreshold = 0.0;
    // A blob's area in pixels must lie in [minArea, maxArea]: smaller ones are glints and
    // noise, larger ones a window or a lamp held against the lens.
    int minArea = 4;
    int maxArea = 5000;
};

struct Blob {
    // Centroid weighted by (pixel − level + 1): sub-pixel, and pixels at the edge of the
    // threshold weigh little, so their discrete inclusion barely moves it.
    double x = 0.0;
    double y = 0.0;
    int area = 0;   // pixels at or above the level (8-connected)
    int peak = 0;   // the brightest pixel's value
    int level = 0;  // the threshold used for this frame
};

class BrightBlobTracker {
public:
    // Throws std::invalid_argument for a config outside the ranges above.
    explicit BrightBlobTracker(const BlobTrackerConfig& config);

    // The 8-connected component of above-level pixels with the most light above the level
    // (Σ (pixel − level + 1)) among those whose area lies in [minArea, maxArea]; nullopt when
    // there is none. Throws std::invalid_argument for a malformed view (checkLuminanceView).
    // One pass over the frame with a union-find over provisional labels; the scratch buffers
    // are kept between calls, so a steady stream of frames allocates nothing.
    std::optional<Blob> find(const LuminanceView& frame);

    const BlobTrackerConfig& config() const { return config_; }

private:
    struct Component {
        std::int64_t weight = 0;
        std::int64_t weightedX = 0;
        std::int64_t weightedY = 0;
        int area = 0;
        int peak = 0;
    };

    std::int32_t newLabel();
    std::int32_t root(std::int32_t label);
    std::int32_t unite(std::int32_t a, std::int32_t b);
    int levelFor(const LuminanceView& frame) const;

    BlobTrackerConfig config_;
    std::vector<std::int32_t> previousRow_;
    std::vector<std::int32_t> currentRow_;
    std::vector<std::int32_t> parent_;   // union-find over labels; label 0 is the background
    std::vector<Component> components_;  // indexed by label
};

}  // namespace vpe::firmware
