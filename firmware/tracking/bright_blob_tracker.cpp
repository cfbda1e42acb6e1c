// SPDX-License-Identifier: MIT
// BrightBlobTracker: one-pass connected components (8-connected) of the above-level pixels.
// Each row remembers its pixels' provisional labels; a pixel takes a neighbour's label from the
// left or the row above and merges the others' into it (union-find), and its light is added to
// its provisional label's sums. At the end every label's sums go to its root. Below-level
// pixels, nearly all of a dark room, cost one comparison.
#include "vpe/firmware/tracking/bright_blob_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vpe::firmware {

BrightBlobTracker::BrightBlobTracker(const BlobTrackerConfig& config) : config_(config) {
    if (config.threshold < 1 || config.threshold > 255) {
        throw std::invalid_argument("blob tracker: threshold must be in 1…255, got " +
                                    std::to_string(config.threshold));
    }
    if (!(config.relativeThreshold >= 0.0 && config.relativeThreshold < 1.0)) {
        throw std::invalid_argument("blob tracker: relative threshold must be in [0, 1), got " +
                                    std::to_string(config.relativeThreshold));
    }
    if (config.minArea < 1 || config.maxArea < config.minArea) {
        throw std::invalid_argument("blob tracker: areas must satisfy 1 ≤ min ≤ max, got [" +
                                    std::to_string(config.minArea) + ", " +
                                    std::to_string(config.maxArea) + "]");
    }
}

std::int32_t BrightBlobTracker::newLabel() {
    const auto label = static_cast<std::int32_t>(parent_.size());
    parent_.push_back(label);
    components_.emplace_back();
    return label;
}

std::int32_t BrightBlobTracker::root(std::int32_t label) {
    while (parent_[static_cast<std::size_t>(label)] != label) {
        // Path halving: every other node on the way points to its grandparent.
        auto& up = parent_[static_cast<std::size_t>(label)];
        up = parent_[static_cast<std::size_t>(up)];
        label = up;
    }
    return label;
}

std::int32_t BrightBlobTracker::unite(std::int32_t a, std::int32_t b) {
    a = root(a);
    b = root(b);
    if (a == b) {
        return a;
    }
    // The smaller label stays the root so that roots are found in few steps from later labels.
    if (b < a) {
        std::swap(a, b);
    }
    parent_[static_cast<std::size_t>(b)] = a;
    return a;
}

int BrightBlobTracker::levelFor(const LuminanceView& frame) const {
    if (config_.relativeThreshold <= 0.0) {
        return config_.threshold;
    }
    int brightest = 0;
    for (int y = 0; y < frame.height; ++y) {
        const std::uint8_t* row = frame.row(y);
        brightest = std::max<int>(brightest, *std::max_element(row, row + frame.width));
    }
    const int relative = static_cast<int>(std::ceil(config_.relativeThreshold * brightest));
    return std::max(config_.threshold, relative);
}

std::optional<Blob> BrightBlobTracker::find(const LuminanceView& frame) {
    checkLuminanceView(frame);
    const int level = levelFor(frame);
    const auto width = static_cast<std::size_t>(frame.width);

    // Rows carry one extra cell on each side so that x − 1 and x + 1 need no bounds checks.
    previousRow_.assign(width + 2, 0);
    currentRow_.assign(width + 2, 0);
    parent_.clear();
    components_.clear();
    newLabel();  // label 0: the background

    for (int y = 0; y < frame.height; ++y) {
        const std::uint8_t* pixels = frame.row(y);
        std::int32_t* current = currentRow_.data() + 1;
        const std::int32_t* above = previousRow_.data() + 1;
        for (int x = 0; x < frame.width; ++x) {
            const int value = pixels[x];
            if (value < level) {
                current[x] = 0;
                continue;
            }
            // Neighbours already visited: left, above-left, above, above-right.
            std::int32_t label = current[x - 1];
            for (const std::int32_t neighbour : {above[x - 1], above[x], above[x + 1]}) {
                if (neighbour == 0) {
                    continue;
                }
                label = label == 0 ? neighbour : unite(label, neighbour);
            }
            if (label == 0) {
                label = newLabel();
            }
            current[x] = label;
            Component& component = components_[static_cast<std::size_t>(label)];
            const int weight = value - level + 1;
            component.weight += weight;
            component.weightedX += static_cast<std::int64_t>(weight) * x;
            component.weightedY += static_cast<std::int64_t>(weight) * y;
            component.area += 1;
            component.peak = std::max(component.peak, value);
        }
        std::swap(previousRow_, currentRow_);
    }

    // Every provisional label's sums go straight to its root; a root keeps its own.
    for (auto label = static_cast<std::int32_t>(components_.size()) - 1; label > 0; --label) {
        const std::int32_t top = root(label);
        if (top == label) {
            continue;
        }
        Component& from = components_[static_cast<std::size_t>(label)];
        Component& to = components_[static_cast<std::size_t>(top)];
        to.weight += from.weight;
        to.weightedX += from.weightedX;
        to.weightedY += from.weightedY;
        to.area += from.area;
        to.peak = std::max(to.peak, from.peak);
        from = Component{};
    }

    const Component* best = nullptr;
    for (std::size_t label = 1; label < components_.size(); ++label) {
        const Component& component = components_[label];
        if (component.area < config_.minArea || component.area > config_.maxArea) {
            continue;
        }
        if (best == nullptr || component.weight > best->weight ||
            (component.weight == best->weight && component.area > best->area)) {
            best = &component;
        }
    }
    if (best == nullptr) {
        return std::nullopt;
    }
    Blob blob;
    blob.x = static_cast<double>(best->weightedX) / static_cast<double>(best->weight);
    blob.y = static_cast<double>(best->weightedY) / static_cast<double>(best->weight);
    blob.area = best->area;
    blob.peak = best->peak;
    blob.level = level;
    return blob;
}

}  // namespace vpe::firmware
