// SPDX-License-Identifier: MIT
// Streak coverage and medial-axis widths, on OpenCV's exact Euclidean distance transform.
#include "vpe/texture/streak_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "vpe/common/input_error.h"
#include "vpe/segment/label_map.h"

namespace vpe::texture {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Linear interpolation between order statistics (type 7, as R and NumPy do by default).
double quantile(const std::vector<float>& sorted, double q) {
    const double position = q * static_cast<double>(sorted.size() - 1);
    const std::size_t below = static_cast<std::size_t>(position);
    const std::size_t above = std::min(below + 1, sorted.size() - 1);
    const double t = position - static_cast<double>(below);
    return static_cast<double>(sorted[below]) +
           t * (static_cast<double>(sorted[above]) - static_cast<double>(sorted[below]));
}

// Exact Euclidean distance from every pixel's centre to the nearest `target` pixel's centre.
cv::Mat distanceTo(const cv::Mat& kinds, StreakPixel target) {
    cv::Mat source(kinds.size(), CV_8U);
    for (int y = 0; y < kinds.rows; ++y) {
        const auto* in = kinds.ptr<std::uint8_t>(y);
        auto* out = source.ptr<std::uint8_t>(y);
        for (int x = 0; x < kinds.cols; ++x) {
            out[x] = in[x] == static_cast<std::uint8_t>(target)
                         ? 0
                         : 255;  // distanceTransform measures to the zero pixels
        }
    }
    cv::Mat distance;
    cv::distanceTransform(source, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    return distance;
}

}  // namespace

StreakStatistics measureStreaks(const StreakMask& mask) {
    StreakStatistics stats;
    const int width = mask.width, height = mask.height;
    for (StreakPixel pixel : mask.pixels) {
        stats.knownPixels += pixel != StreakPixel::kUnknown ? 1 : 0;
        stats.streakPixels += pixel == StreakPixel::kStreak ? 1 : 0;
    }
    stats.coverage = stats.knownPixels > 0 ? static_cast<double>(stats.streakPixels) /
                                                 static_cast<double>(stats.knownPixels)
                                           : kNaN;

    // The map in a frame of unknown pixels one pixel wide; a map that wraps in u is laid
    // between copies of itself first, so bands crossing the seam measure whole.
    const int copies = mask.wrapsU ? width : 0;
    const int pad = copies + 1;
    const int frameWidth = width + 2 * pad, frameHeight = height + 2;
    cv::Mat kinds(frameHeight, frameWidth, CV_8U,
                  cv::Scalar(static_cast<std::uint8_t>(StreakPixel::kUnknown)));
    for (int y = 0; y < height; ++y) {
        auto* row = kinds.ptr<std::uint8_t>(y + 1);
        for (int x = -copies; x < width + copies; ++x) {
            const int source = ((x % width) + width) % width;
            row[x + pad] = static_cast<std::uint8_t>(
                mask.pixels[static_cast<std::size_t>(y) * width + source]);
        }
    }
    const cv::Mat toBackground = distanceTo(kinds, StreakPixel::kBackground);
    const cv::Mat toUnknown = distanceTo(kinds, StreakPixel::kUnknown);

    // Medial-axis pixels anywhere in the frame (in the copies too: their discs reach the map).
    struct Centre {
        int x, y;
        float radius, width;
        bool trusted;
    };
    std::vector<Centre> centres;
    static constexpr int kAxes[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
    for (int y = 1; y <= height; ++y) {
        for (int x = 1; x + 1 < frameWidth; ++x) {
            if (kinds.at<std::uint8_t>(y, x) != static_cast<std::uint8_t>(StreakPixel::kStreak)) {
                continue;
            }
            const float d = toBackground.at<float>(y, x);
            bool ridge = false, strict = false;
            for (const auto& axis : kAxes) {
                const float before = toBackground.at<float>(y - axis[1], x - axis[0]);
                const float after = toBackground.at<float>(y + axis[1], x + axis[0]);
                if (d >= before && d >= after && (d > before || d > after)) {
                    ridge = true;
                    strict = strict || (d > before && d > after);
                }
            }
            if (ridge) {
                // The band may go on where nothing is known: trusted only when the nearest
                // background is nearer than every unknown pixel.
                centres.push_back(
                    {x, y, d, strict ? 2 * d - 1 : 2 * d, d < toUnknown.at<float>(y, x)});
            }
        }
    }
    // Local thickness: every streak pixel takes the width of the widest medial disc that
    // holds it (the disc of centre c and radius D(c) holds only streak pixels).
    cv::Mat thickness(frameHeight, frameWidth, CV_32F, cv::Scalar(0.0f));
    cv::Mat trusted(frameHeight, frameWidth, CV_8U, cv::Scalar(0));
    for (const Centre& c : centres) {
        const int reach = static_cast<int>(std::ceil(c.radius));
        const float radiusSquared = c.radius * c.radius;
        for (int dy = -reach; dy <= reach; ++dy) {
            const int y = c.y + dy;
            if (y < 1 || y > height) {
                continue;
            }
            for (int dx = -reach; dx <= reach; ++dx) {
                const int x = c.x + dx;
                if (x < pad || x >= pad + width ||
                    static_cast<float>(dx * dx + dy * dy) >= radiusSquared) {
                    continue;
                }
                float& best = thickness.at<float>(y, x);
                std::uint8_t& bestTrusted = trusted.at<std::uint8_t>(y, x);
                if (c.width > best) {
                    best = c.width;
                    bestTrusted = c.trusted ? 1 : 0;
                } else if (c.width == best && c.trusted) {
                    bestTrusted = 1;
                }
            }
        }
    }
    for (int y = 1; y <= height; ++y) {
        for (int x = pad; x < pad + width; ++x) {
            if (kinds.at<std::uint8_t>(y, x) == static_cast<std::uint8_t>(StreakPixel::kStreak) &&
                trusted.at<std::uint8_t>(y, x) != 0) {
                stats.widths.push_back(thickness.at<float>(y, x));
            }
        }
    }
    if (stats.widths.empty()) {
        stats.widthQuartile1 = stats.widthMedian = stats.widthQuartile3 = stats.widthMean =
            stats.widthLogSpread = kNaN;
        return stats;
    }
    std::vector<float> sorted = stats.widths;
    std::sort(sorted.begin(), sorted.end());
    stats.widthQuartile1 = quantile(sorted, 0.25);
    stats.widthMedian = quantile(sorted, 0.5);
    stats.widthQuartile3 = quantile(sorted, 0.75);
    double sum = 0;
    for (float w : sorted) {
        sum += static_cast<double>(w);
    }
    stats.widthMean = sum / static_cast<double>(sorted.size());
    // 1.349 = the interquartile range of a unit normal.
    stats.widthLogSpread = std::log(stats.widthQuartile3 / stats.widthQuartile1) / 1.349;
    return stats;
}

StreakMask streakMaskFromLabels(const segment::LabelMap& labels, int region) {
    StreakMask mask;
    mask.width = labels.width;
    mask.height = labels.height;
    mask.pixels.assign(labels.values.size(), StreakPixel::kUnknown);
    for (std::size_t p = 0; p < labels.values.size(); ++p) {
        const std::uint8_t label = labels.values[p];
        mask.pixels[p] = label == segment::LabelMap::kNoLabel ? StreakPixel::kUnknown
                         : label == region                    ? StreakPixel::kStreak
                                                              : StreakPixel::kBackground;
    }
    return mask;
}

StreakMask streakMaskFromWeights(const std::vector<float>& weight, int width, int height,
                                 bool wrapsU, float threshold) {
    StreakMask mask;
    mask.width = width;
    mask.height = height;
    mask.wrapsU = wrapsU;
    mask.pixels.assign(weight.size(), StreakPixel::kBackground);
    for (std::size_t p = 0; p < weight.size(); ++p) {
        mask.pixels[p] = weight[p] >= threshold ? StreakPixel::kStreak : StreakPixel::kBackground;
    }
    return mask;
}

StreakStatistics measureLabelStreaks(const std::filesystem::path& labels, int region) {
    const segment::LabelMap map = segment::readLabelImage(labels);
    if (region < 0 || region >= map.labels) {
        throw common::InputError(labels, "has labels 0.." + std::to_string(map.labels - 1) +
                                             ", not region " + std::to_string(region));
    }
    StreakStatistics stats = measureStreaks(streakMaskFromLabels(map, region));
    if (stats.streakPixels == 0) {
        throw common::InputError(labels, "region " + std::to_string(region) + " has no pixels");
    }
    return stats;
}

}  // namespace vpe::texture
