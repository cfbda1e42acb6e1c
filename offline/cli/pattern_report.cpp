// SPDX-License-Identifier: MIT
// The pattern entries' report shared by `vpe compose` and `vpe weights`.
#include "cli/pattern_report.h"

#include <cstdio>

#include "vpe/texture/streak_statistics.h"
#include "vpe/texture/stroke_pattern.h"
#include "vpe/texture/weight_maps.h"

namespace vpe::cli {

namespace {

nlohmann::json streakJson(const texture::StreakStatistics& stats) {
    return {{"coverage", stats.coverage},
            {"width_quartile1", stats.widthQuartile1},
            {"width_median", stats.widthMedian},
            {"width_quartile3", stats.widthQuartile3},
            {"width_log_spread", stats.widthLogSpread},
            {"medial_axis_pixels", stats.widths.size()}};
}

nlohmann::json describeStrokes(const texture::WeightSource& source,
                               const texture::WeightMaps& weights, int region) {
    const texture::ResolvedStrokes resolved = texture::resolveStrokes(source.strokes);
    const texture::StreakStatistics composed =
        texture::measureStreaks(texture::streakMaskFromWeights(
            weights.alpha[static_cast<std::size_t>(region)], weights.width, weights.height,
            resolved.wrap != texture::StrokeWrap::kNone));
    // The body width and spread fitted to a source are known only by drawing again.
    double bodyWidth = resolved.width, spread = resolved.spread;
    if (resolved.fitWidth || resolved.fitSpread) {
        const texture::StrokePattern drawn =
            texture::generateStrokes(resolved, weights.width, weights.height);
        bodyWidth = drawn.bodyWidth;
        spread = drawn.spread;
    }
    std::fprintf(stderr, "strokes for region %d: body width %.1f texels (spread %.2f), ", region,
                 bodyWidth, spread);
    if (resolved.count > 0) {
        std::fprintf(stderr, "%d strokes", resolved.count);
    } else {
        std::fprintf(stderr, "coverage %.3f", resolved.coverage);
    }
    std::fprintf(stderr, "; α ≥ ½ covers %.3f, medial-axis width %.1f (quartiles %.1f, %.1f)",
                 composed.coverage, composed.widthMedian, composed.widthQuartile1,
                 composed.widthQuartile3);
    if (resolved.source) {
        std::fprintf(stderr, "; the source's region covers %.3f, width %.1f (%.1f, %.1f)",
                     resolved.source->coverage, resolved.source->widthMedian,
                     resolved.source->widthQuartile1, resolved.source->widthQuartile3);
    }
    std::fprintf(stderr, "\n");
    nlohmann::json json = {{"region", region},
                           {"width", bodyWidth},
                           {"spread", spread},
                           {"coverage", resolved.coverage},
                           {"count", resolved.count},
                           {"length", resolved.length},
                           {"softness", resolved.softness},
                           {"composed", streakJson(composed)}};
    if (resolved.source) {
        json["source"] = streakJson(*resolved.source);
    }
    return json;
}

nlohmann::json describeQuilted(const texture::WeightSource& source,
                               const texture::WeightMaps& weights, int region) {
    const texture::StreakStatistics composed =
        texture::measureStreaks(texture::streakMaskFromWeights(
            weights.alpha[static_cast<std::size_t>(region)], weights.width, weights.height,
            /*wrapsU=*/false));
    const texture::StreakStatistics labels =
        texture::measureLabelStreaks(source.labelQuilt.labels, source.labelQuilt.region);
    std::fprintf(stderr,
                 "quilted labels for region %d: α ≥ ½ covers %.3f, medial-axis width %.1f "
                 "(quartiles %.1f, %.1f); the source's region covers %.3f, width %.1f (%.1f, "
                 "%.1f)\n",
                 region, composed.coverage, composed.widthMedian, composed.widthQuartile1,
                 composed.widthQuartile3, labels.coverage, labels.widthMedian,
                 labels.widthQuartile1, labels.widthQuartile3);
    return {{"region", region}, {"composed", streakJson(composed)}, {"source", streakJson(labels)}};
}

}  // namespace

void reportPatterns(const std::vector<texture::WeightSource>& sources,
                    const texture::WeightMaps& weights, nlohmann::json& json) {
    nlohmann::json strokes = nlohmann::json::array(), quilted = nlohmann::json::array();
    for (std::size_t k = 0; k < sources.size(); ++k) {
        if (sources[k].invert) {
            continue;
        }
        if (sources[k].kind == texture::WeightKind::kStrokes) {
            strokes.push_back(describeStrokes(sources[k], weights, static_cast<int>(k)));
        } else if (sources[k].kind == texture::WeightKind::kQuilted) {
            quilted.push_back(describeQuilted(sources[k], weights, static_cast<int>(k)));
        }
    }
    json["strokes"] = std::move(strokes);
    json["quilted"] = std::move(quilted);
}

}  // namespace vpe::cli
