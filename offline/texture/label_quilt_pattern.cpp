// SPDX-License-Identifier: MIT
// Quilting a label map: signed distance in, Image Quilting, a soft weight out.
#include "vpe/texture/label_quilt_pattern.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "vpe/common/input_error.h"
#include "vpe/quilt/image_quilter.h"
#include "vpe/segment/label_map.h"
#include "vpe/texture/streak_statistics.h"

namespace vpe::texture {

namespace {

// Exact Euclidean distance from every pixel to the nearest pixel where `mask` is 0.
cv::Mat distanceToZero(const cv::Mat& mask) {
    cv::Mat distance;
    cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    return distance;
}

}  // namespace

std::vector<float> quiltLabelPattern(const LabelQuiltParameters& p, int width, int height) {
    const segment::LabelMap labels = segment::readLabelImage(p.labels);
    if (p.region < 0 || p.region >= labels.labels) {
        throw common::InputError(p.labels, "has labels 0.." + std::to_string(labels.labels - 1) +
                                               ", not region " + std::to_string(p.region));
    }
    int block = 0;
    if (p.block) {
        block = *p.block;
    } else {
        const StreakStatistics streaks = measureStreaks(streakMaskFromLabels(labels, p.region));
        if (std::isnan(streaks.widthMedian)) {
            throw common::InputError(p.labels,
                                     "region " + std::to_string(p.region) +
                                         " has no band whose width can be measured (give block=)");
        }
        block = std::max(8, static_cast<int>(std::lround(4 * streaks.widthMedian)));
    }
    const int overlap = p.overlap.value_or(std::max(2, block / 6));

    // Signed distance to the region's edge, between pixel centres: +D inside (to the nearest
    // pixel outside), −D outside; clipped, as farther pixels say nothing more about the edge.
    cv::Mat inside(labels.height, labels.width, CV_8U), outside(labels.height, labels.width, CV_8U);
    std::vector<std::uint8_t> labelled(labels.values.size());
    for (std::size_t i = 0; i < labels.values.size(); ++i) {
        const bool in = labels.values[i] == p.region;
        inside.data[i] = in ? 255 : 0;
        outside.data[i] = in ? 0 : 255;
        labelled[i] = labels.values[i] == segment::LabelMap::kNoLabel ? 1 : 0;  // quilt "region" 0
    }
    const cv::Mat toOutside = distanceToZero(inside), toInside = distanceToZero(outside);
    const float clip = 0.5f * static_cast<float>(block);
    model::CoefficientImage source;
    source.width = labels.width;
    source.height = labels.height;
    source.dims = 1;
    source.values.resize(labels.values.size());
    for (std::size_t i = 0; i < labels.values.size(); ++i) {
        const float inner = reinterpret_cast<const float*>(toOutside.data)[i];
        const float outer = reinterpret_cast<const float*>(toInside.data)[i];
        source.values[i] = std::clamp(inner > 0 ? inner - 0.5f : 0.5f - outer, -clip, clip);
    }

    quilt::QuiltSettings settings;
    settings.block = block;
    settings.overlap = overlap;
    settings.seed = p.seed;
    settings.threads = std::max(1u, std::thread::hardware_concurrency());
    quilt::RegionQuilt quilted;
    try {
        quilted = quilt::quiltRegion(source, labelled, 0, width, height, settings);
    } catch (const common::InputError& error) {
        throw common::InputError(p.labels, std::string("cannot be quilted: ") + error.what());
    }
    std::vector<float> weight(static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < weight.size(); ++i) {
        const float distance =
            source.at(quilted.sourceX[i], quilted.sourceY[i])[0];  // the copied pixel's
        weight[i] = p.softness > 0
                        ? std::clamp(0.5f + distance / static_cast<float>(p.softness), 0.0f, 1.0f)
                        : (distance > 0 ? 1.0f : 0.0f);
    }
    return weight;
}

}  // namespace vpe::texture
