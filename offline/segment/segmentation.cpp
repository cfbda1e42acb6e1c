// SPDX-License-Identifier: MIT
// Seeded and automatic segmentation of an appearance.
#include "vpe/segment/segmentation.h"

#include <cmath>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/segment/kmeans.h"

namespace vpe::segment {

namespace {

std::string seedName(const PixelSeed& seed) {
    return "seed (" + std::to_string(seed.x) + ", " + std::to_string(seed.y) + ")";
}

LabelMap clusterLabels(const Appearance& appearance, const SegmentOptions& options,
                       SegmentResult& result) {
    // Only valid pixels are clustered.
    const int dims = appearance.featureCount;
    std::vector<float> points;
    points.reserve(appearance.validPixels * static_cast<std::size_t>(dims));
    for (std::size_t p = 0; p < appearance.valid.size(); ++p) {
        if (appearance.valid[p]) {
            const float* f = &appearance.features[p * static_cast<std::size_t>(dims)];
            points.insert(points.end(), f, f + dims);
        }
    }
    KMeansOptions kmeans;
    kmeans.seed = options.seed;
    kmeans.threads = options.threads;
    std::vector<int> labels;
    if (options.clusters > 0) {
        kmeans.clusters = options.clusters;
        labels = kMeans(points, dims, kmeans).labels;
        result.clusters = options.clusters;
    } else {
        ClusterCountChoice choice =
            chooseClusterCount(points, dims, options.minClusters, options.maxClusters, kmeans);
        labels = std::move(choice.result.labels);
        result.clusters = choice.chosen;
        result.candidates = choice.candidates;
        result.silhouettes = choice.silhouettes;
    }
    LabelMap map;
    map.width = appearance.width;
    map.height = appearance.height;
    map.labels = result.clusters;
    map.values.assign(appearance.valid.size(), LabelMap::kNoLabel);
    std::size_t i = 0;
    for (std::size_t p = 0; p < appearance.valid.size(); ++p) {
        if (appearance.valid[p]) {
            map.values[p] = static_cast<std::uint8_t>(labels[i++]);
        }
    }
    return map;
}

}  // namespace

SegmentResult segmentAppearance(const Appearance& appearance, const SegmentOptions& options) {
    SegmentResult result;
    if (!options.seeds.empty()) {
        if (options.seeds.size() > static_cast<std::size_t>(LabelMap::kMaxLabels)) {
            throw common::InputError("--seeds: at most " + std::to_string(LabelMap::kMaxLabels) +
                                     " seeds (one label each)");
        }
        for (const PixelSeed& seed : options.seeds) {
            if (seed.x < 0 || seed.y < 0 || seed.x >= appearance.width ||
                seed.y >= appearance.height) {
                throw common::InputError("--seeds: " + seedName(seed) + " is outside the " +
                                         std::to_string(appearance.width) + "x" +
                                         std::to_string(appearance.height) + " model");
            }
            if (!appearance.valid[appearance.pixel(seed.x, seed.y)]) {
                throw common::InputError("--seeds: " + seedName(seed) +
                                         " has no valid fit in the model");
            }
        }
        result.map = labelBySeeds(appearance, options.seeds, options.seedSpace);
    } else {
        const int k = options.clusters;
        if (k < 0 || k > LabelMap::kMaxLabels) {
            throw common::InputError("--auto: K must be between 1 and " +
                                     std::to_string(LabelMap::kMaxLabels) + ", not " +
                                     std::to_string(k));
        }
        const std::size_t needed = static_cast<std::size_t>(k > 0 ? k : options.minClusters);
        if (appearance.validPixels < needed) {
            throw common::InputError("--auto: " + std::to_string(needed) +
                                     " labels need as many valid "
                                     "pixels; the model has " +
                                     std::to_string(appearance.validPixels));
        }
        result.map = clusterLabels(appearance, options, result);
    }
    result.minIsland =
        options.minIsland >= 0
            ? static_cast<std::size_t>(options.minIsland)
            : static_cast<std::size_t>(
                  std::ceil(kDefaultIslandShare * static_cast<double>(appearance.validPixels)));
    result.islandsMerged = removeIslands(result.map, result.minIsland);
    // Seeded labels keep the seeds' order (label i is seed i's region, as the user chose);
    // clusters have no order of their own, so they are put in one.
    if (options.seeds.empty()) {
        orderLabelsByLuminance(result.map, appearance);
    }
    return result;
}

}  // namespace vpe::segment
