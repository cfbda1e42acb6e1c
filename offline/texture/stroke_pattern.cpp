// SPDX-License-Identifier: MIT
// Hidasuki strokes: smooth random curves swept with a varying width and a soft edge.
#include "vpe/texture/stroke_pattern.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/common/random_bits.h"

namespace vpe::texture {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Counter-based random numbers: value i of stream `key` depends on nothing else.
class RandomStream {
public:
    explicit RandomStream(std::uint64_t key) : key_(key) {}
    double uniform() { return common::uniformFromBits(common::mixBits(key_ + counter_++)); }
    double normal() {                       // Box–Muller
        const double u1 = 1.0 - uniform();  // (0, 1]
        const double u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * kPi * u2);
    }

private:
    std::uint64_t key_;
    std::uint64_t counter_ = 0;
};

std::uint64_t streamKey(std::uint64_t seed, std::uint64_t stroke, std::uint64_t channel) {
    return common::mixBits(common::mixBits(seed ^ 0x68696461ull) + stroke * 0x9E3779B97F4A7C15ull +
                           channel * 0xD1B54A32D192ED03ull);
}

// A smooth random function of t with unit variance everywhere: Catmull–Rom through standard
// normal values at the integers, divided by the interpolation's own standard deviation there
// (a smooth factor, 1 at the knots, with zero slope there, so the result stays C¹).
class SmoothNoise {
public:
    explicit SmoothNoise(std::uint64_t key) : key_(key) {}
    double at(double t) const {
        const double cell = std::floor(t);
        const double f = t - cell;
        const double f2 = f * f, f3 = f2 * f;
        const double w[4] = {0.5 * (-f3 + 2 * f2 - f), 0.5 * (3 * f3 - 5 * f2 + 2),
                             0.5 * (-3 * f3 + 4 * f2 + f), 0.5 * (f3 - f2)};
        const auto base = static_cast<std::int64_t>(cell) - 1;
        double value = 0, variance = 0;
        for (int i = 0; i < 4; ++i) {
            value += w[i] * knot(base + i);
            variance += w[i] * w[i];
        }
        return value / std::sqrt(variance);
    }

private:
    double knot(std::int64_t i) const {
        RandomStream stream(common::mixBits(key_ + static_cast<std::uint64_t>(i)));
        return stream.normal();
    }
    std::uint64_t key_;
};

// One stroke as a polyline with a full width at every vertex.
struct StrokePath {
    std::vector<double> x, y, width;
};

StrokePath traceStroke(const ResolvedStrokes& s, int index, int mapWidth, int mapHeight) {
    RandomStream random(streamKey(s.seed, static_cast<std::uint64_t>(index), 0));
    const bool wrapsU = s.wrap != StrokeWrap::kNone;
    const bool wrapsV = s.wrap == StrokeWrap::kUV;
    // Midpoints cover the map evenly; along an axis that does not wrap they also fall half a
    // mean length outside, so strokes entering from beyond the edge keep the edge as dense.
    const double midX = wrapsU ? random.uniform() * mapWidth
                               : random.uniform() * (mapWidth + s.length) - 0.5 * s.length;
    const double midY = wrapsV ? random.uniform() * mapHeight
                               : random.uniform() * (mapHeight + s.length) - 0.5 * s.length;
    const double heading = (s.angleDegrees + s.angleSpread * (random.uniform() - 0.5)) * kPi / 180;
    const double length = s.length * (0.5 + random.uniform());
    const double bodyWidth = s.width * std::exp(s.spread * random.normal());
    const SmoothNoise wander(streamKey(s.seed, static_cast<std::uint64_t>(index), 1));
    const SmoothNoise thickness(streamKey(s.seed, static_cast<std::uint64_t>(index), 2));
    const double wanderOffset = 1e3 * random.uniform(), thicknessOffset = 1e3 * random.uniform();
    const double bend = s.bend * kPi / 180;
    const double wanderScale = s.length / 3;  // knots of the heading's wander
    const double thicknessScale = 4 * s.width;
    // Ends round off over two body widths (at most a quarter of the stroke): an elliptic cap.
    const double cap = std::min(2 * bodyWidth, 0.25 * length);
    const double step = std::max(0.5, 0.25 * bodyWidth);
    const int segments = std::max(1, static_cast<int>(std::ceil(length / step)));
    const double ds = length / segments;

    StrokePath path;
    double x = 0, y = 0;
    for (int i = 0; i <= segments; ++i) {
        const double along = i * ds;
        const double fromEnd = std::min(along, length - along);
        const double f = std::clamp(fromEnd / cap, 0.0, 1.0);
        path.x.push_back(x);
        path.y.push_back(y);
        path.width.push_back(
            bodyWidth * std::sqrt(f * (2 - f)) *
            std::exp(s.wobble * thickness.at(thicknessOffset + along / thicknessScale)));
        // Midpoint rule; image y points down, so counter-clockwise as seen is −y.
        const double theta =
            heading + bend * wander.at(wanderOffset + (along + 0.5 * ds) / wanderScale);
        x += ds * std::cos(theta);
        y -= ds * std::sin(theta);
    }
    // Place the stroke's middle vertex at the drawn midpoint.
    const std::size_t middle = static_cast<std::size_t>(segments / 2);
    const double shiftX = midX - path.x[middle], shiftY = midY - path.y[middle];
    for (std::size_t i = 0; i < path.x.size(); ++i) {
        path.x[i] += shiftX;
        path.y[i] += shiftY;
    }
    return path;
}

// Hermite smoothstep from 1 (distance ≤ inner) to 0 (distance ≥ outer).
double edgeProfile(double distance, double half, double softness) {
    if (softness <= 0) {
        return distance <= half ? 1.0 : 0.0;
    }
    const double t = std::clamp((distance - (half - 0.5 * softness)) / softness, 0.0, 1.0);
    return 1.0 - t * t * (3 - 2 * t);
}

// One stroke's weight, max over its segments' capsules, into a layer of the map's size; the
// pixels it touched are listed so the layer can be merged and cleared cheaply.
class StrokeLayer {
public:
    StrokeLayer(int width, int height, StrokeWrap wrap)
        : width_(width),
          height_(height),
          wrap_(wrap),
          value_(static_cast<std::size_t>(width) * height, 0.0f) {}

    void draw(const StrokePath& path, double softness) {
        for (std::size_t i = 0; i + 1 < path.x.size(); ++i) {
            drawSegment(path.x[i], path.y[i], path.width[i], path.x[i + 1], path.y[i + 1],
                        path.width[i + 1], softness);
        }
    }
    const std::vector<std::size_t>& touched() const { return touched_; }
    float at(std::size_t pixel) const { return value_[pixel]; }
    void clear() {
        for (std::size_t pixel : touched_) {
            value_[pixel] = 0;
        }
        touched_.clear();
    }

private:
    void drawSegment(double x0, double y0, double w0, double x1, double y1, double w1,
                     double softness) {
        const double reach = 0.5 * std::max(w0, w1) + 0.5 * softness;
        const int left = static_cast<int>(std::floor(std::min(x0, x1) - reach - 0.5));
        const int right = static_cast<int>(std::ceil(std::max(x0, x1) + reach));
        const int top = static_cast<int>(std::floor(std::min(y0, y1) - reach - 0.5));
        const int bottom = static_cast<int>(std::ceil(std::max(y0, y1) + reach));
        const double dx = x1 - x0, dy = y1 - y0;
        const double lengthSquared = dx * dx + dy * dy;
        for (int py = top; py <= bottom; ++py) {
            int y = py;
            if (wrap_ == StrokeWrap::kUV) {
                y = ((py % height_) + height_) % height_;
            } else if (py < 0 || py >= height_) {
                continue;
            }
            for (int px = left; px <= right; ++px) {
                int x = px;
                if (wrap_ != StrokeWrap::kNone) {
                    x = ((px % width_) + width_) % width_;
                } else if (px < 0 || px >= width_) {
                    continue;
                }
                // Pixel centres, in the unwrapped plane the stroke was traced in.
                const double cx = px + 0.5 - x0, cy = py + 0.5 - y0;
                const double t = lengthSquared > 0
                                     ? std::clamp((cx * dx + cy * dy) / lengthSquared, 0.0, 1.0)
                                     : 0.0;
                const double distance = std::hypot(cx - t * dx, cy - t * dy);
                const double value = edgeProfile(distance, 0.5 * (w0 + t * (w1 - w0)), softness);
                if (value <= 0) {
                    continue;
                }
                const std::size_t pixel = static_cast<std::size_t>(y) * width_ + x;
                float& stored = value_[pixel];
                if (stored == 0) {
                    touched_.push_back(pixel);
                }
                stored = std::max(stored, static_cast<float>(value));
            }
        }
    }

    int width_, height_;
    StrokeWrap wrap_;
    std::vector<float> value_;
    std::vector<std::size_t> touched_;
};

}  // namespace

ResolvedStrokes resolveStrokes(const StrokeParameters& p) {
    ResolvedStrokes s;
    if (!p.labels.empty()) {
        s.source = measureLabelStreaks(p.labels, p.region.value_or(0));
        if (std::isnan(s.source->widthMedian)) {
            throw common::InputError(p.labels, "region " + std::to_string(p.region.value_or(0)) +
                                                   " has no band whose width can be measured");
        }
    }
    s.fitWidth = s.source && !p.width;
    s.fitSpread = s.source && !p.spread;
    s.count = p.count.value_or(0);
    s.coverage = s.count > 0 ? 0.0 : p.coverage.value_or(s.source ? s.source->coverage : 0.25);
    s.width = p.width.value_or(s.source ? s.source->widthMedian : 12.0);
    s.spread = p.spread.value_or(s.source ? s.source->widthLogSpread : 0.25);
    s.wobble = p.wobble;
    s.length = p.length.value_or(32 * s.width);
    s.bend = p.bend;
    s.softness = p.softness.value_or(0.4 * s.width);
    s.angleDegrees = p.angleDegrees;
    s.angleSpread = p.angleSpread;
    s.seed = p.seed;
    s.wrap = p.wrap;
    return s;
}

namespace {

StrokePattern drawStrokes(const ResolvedStrokes& s, int width, int height) {
    StrokePattern pattern;
    pattern.bodyWidth = s.width;
    pattern.spread = s.spread;
    pattern.weight.assign(static_cast<std::size_t>(width) * height, 0.0f);
    const double pixels = static_cast<double>(width) * height;
    const double target = s.coverage * pixels;
    // Strokes a Boolean model of this coverage needs; a cap on attempts far above it ends the
    // loop even if strokes kept missing the map.
    const double strokeArea = std::max(s.width * s.length, 1.0);
    const double expected = s.count > 0 ? s.count : -std::log(1 - s.coverage) * pixels / strokeArea;
    const int attempts = static_cast<int>(std::min(1000 + 100 * expected, 1e7));
    StrokeLayer layer(width, height, s.wrap);
    double covered = 0;
    for (int index = 0; index < attempts; ++index) {
        layer.draw(traceStroke(s, index, width, height), s.softness);
        if (layer.touched().empty()) {
            continue;  // drawn wholly beyond an edge that does not wrap: not a stroke of the map
        }
        std::size_t gain = 0;
        for (std::size_t pixel : layer.touched()) {
            gain += pattern.weight[pixel] < 0.5f && layer.at(pixel) >= 0.5f ? 1 : 0;
        }
        // Past the target, keep the stroke only if it lands nearer than stopping short.
        const bool last = s.count == 0 && covered + static_cast<double>(gain) >= target;
        if (!last || pattern.strokes == 0 ||
            covered + static_cast<double>(gain) - target <= target - covered) {
            for (std::size_t pixel : layer.touched()) {
                pattern.weight[pixel] = std::max(pattern.weight[pixel], layer.at(pixel));
            }
            covered += static_cast<double>(gain);
            ++pattern.strokes;
        }
        layer.clear();
        if (last || (s.count > 0 && pattern.strokes == s.count)) {
            break;
        }
    }
    pattern.coverage = covered / pixels;
    return pattern;
}

}  // namespace

StrokePattern generateStrokes(const ResolvedStrokes& s, int width, int height) {
    if (!s.source || (!s.fitWidth && !s.fitSpread)) {
        return drawStrokes(s, width, height);
    }
    const double targetWidth = s.source->widthMedian;
    const double targetSpread = s.source->widthLogSpread;
    constexpr int kRounds = 4;
    ResolvedStrokes trial = s;
    StrokePattern best;
    double bestError = INFINITY;
    int rounds = 0;
    for (int round = 1; round <= kRounds; ++round) {
        rounds = round;
        StrokePattern pattern = drawStrokes(trial, width, height);
        const StreakStatistics measured = measureStreaks(
            streakMaskFromWeights(pattern.weight, width, height, trial.wrap != StrokeWrap::kNone));
        if (std::isnan(measured.widthMedian)) {
            return pattern;  // nothing measurable to fit (a map too small for its strokes)
        }
        const double widthError =
            s.fitWidth ? std::fabs(measured.widthMedian / targetWidth - 1) : 0.0;
        const double spreadError =
            s.fitSpread ? std::fabs(measured.widthLogSpread - targetSpread) : 0.0;
        const double error = widthError + spreadError;
        if (error < bestError) {
            bestError = error;
            best = std::move(pattern);
        }
        // Within 2% in width and 0.03 in log spread: the measurement's own resolution.
        if (widthError <= 0.02 && spreadError <= 0.03) {
            break;
        }
        if (s.fitWidth) {
            trial.width = std::max(0.5, trial.width * targetWidth / measured.widthMedian);
        }
        if (s.fitSpread) {
            trial.spread =
                std::clamp(trial.spread + targetSpread - measured.widthLogSpread, 0.0, 2.0);
        }
    }
    best.fitRounds = rounds;
    return best;
}

}  // namespace vpe::texture
