// SPDX-License-Identifier: MIT
// The procedural jar: a smooth profile through a few control points, swept about y.
#include "vpe/scene/procedural_vase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "vpe/common/input_error.h"

namespace vpe::scene {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The profile in units of the height: (y / height, radius / height). A Bizen tsubo: a foot
// narrower than the body, the widest point a little below half height, a high rounded
// shoulder, a short neck and a lip that flares out again.
struct ProfilePoint {
    double y, r;
};
constexpr std::array<ProfilePoint, 9> kProfile{{
    {0.00, 0.30},
    {0.05, 0.35},
    {0.20, 0.46},
    {0.42, 0.53},
    {0.60, 0.50},
    {0.75, 0.39},
    {0.86, 0.25},
    {0.93, 0.225},
    {1.00, 0.27},
}};

// Tangent dr/dy at control point k: the average of the neighbouring chords' slopes (one
// chord at the ends), which makes the profile a C¹ cubic Hermite spline.
double controlSlope(std::size_t k) {
    const auto chord = [](std::size_t a) {
        return (kProfile[a + 1].r - kProfile[a].r) / (kProfile[a + 1].y - kProfile[a].y);
    };
    if (k == 0) {
        return chord(0);
    }
    if (k == kProfile.size() - 1) {
        return chord(k - 1);
    }
    return 0.5 * (chord(k - 1) + chord(k));
}

// Radius / height and its derivative with respect to y / height, at t = y / height.
std::array<double, 2> profile(double t) {
    t = std::clamp(t, 0.0, 1.0);
    std::size_t k = 0;
    while (k + 2 < kProfile.size() && t > kProfile[k + 1].y) {
        ++k;
    }
    const double span = kProfile[k + 1].y - kProfile[k].y;
    const double s = (t - kProfile[k].y) / span;
    const double p0 = kProfile[k].r, p1 = kProfile[k + 1].r;
    const double m0 = controlSlope(k) * span, m1 = controlSlope(k + 1) * span;
    const double s2 = s * s, s3 = s2 * s;
    const double value = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 +
                         (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
    const double derivative = ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 +
                               (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * m1) /
                              span;
    return {value, derivative};
}

// y as a function of arc length along the side, tabulated.
class ArcLengthTable {
public:
    explicit ArcLengthTable(double height) : height_(height) {
        arc_.resize(kSamples + 1);
        arc_[0] = 0;
        for (int k = 1; k <= kSamples; ++k) {
            const double y0 = height * (k - 1) / kSamples, y1 = height * k / kSamples;
            const double dr = vaseRadius(y1, height) - vaseRadius(y0, height);
            arc_[static_cast<std::size_t>(k)] =
                arc_[static_cast<std::size_t>(k - 1)] + std::hypot(dr, y1 - y0);
        }
    }
    double length() const { return arc_.back(); }
    double heightAt(double arc) const {
        if (arc >= length()) {
            return height_;
        }
        const auto upper = std::upper_bound(arc_.begin(), arc_.end(), arc);
        const auto k = static_cast<std::size_t>(
            std::max<std::ptrdiff_t>(1, std::distance(arc_.begin(), upper)));
        const double a0 = arc_[k - 1], a1 = arc_[k];
        const double f = a1 > a0 ? (arc - a0) / (a1 - a0) : 0.0;
        return height_ * (static_cast<double>(k - 1) + f) / kSamples;
    }

private:
    static constexpr int kSamples = 4096;
    double height_;
    std::vector<double> arc_;
};

}  // namespace

double vaseRadius(double y, double height) {
    return height * profile(y / height)[0];
}

double vaseRadiusSlope(double y, double height) {
    return profile(y / height)[1];
}

ScreenMesh makeProceduralVase(const VaseParameters& parameters) {
    const auto& p = parameters;
    if (!(p.height > 0) || !std::isfinite(p.height)) {
        throw common::InputError("vase: height must be a positive number of metres");
    }
    if (p.segments < 3 || p.segments > 65536 || p.rings < 1 || p.rings > 65536 || p.baseRings < 1 ||
        p.baseRings > 65536) {
        throw common::InputError(
            "vase: segments must be 3..65536 and rings, base rings 1..65536 (got " +
            std::to_string(p.segments) + ", " + std::to_string(p.rings) + ", " +
            std::to_string(p.baseRings) + ")");
    }
    const auto columns = static_cast<std::uint32_t>(p.segments + 1);  // seam duplicated
    const std::uint64_t vertexTotal =
        static_cast<std::uint64_t>(p.segments) +
        std::uint64_t{columns} * static_cast<std::uint64_t>(p.baseRings + p.rings + 1);
    requireIndexableVertexCount(vertexTotal, "vase");

    const ArcLengthTable arc(p.height);
    const double footRadius = vaseRadius(0, p.height);
    const double totalArc = footRadius + arc.length();

    ScreenMesh mesh;
    mesh.positions.reserve(vertexTotal);
    mesh.normals.reserve(vertexTotal);
    mesh.uvs.reserve(vertexTotal);
    // Column i of every ring sits at the same angle; the last column repeats the first one's
    // position exactly (not sin 2π), so seam vertices coincide bit for bit.
    const auto addVertex = [&](int column, double radius, double y, double slope, bool bottom,
                               double u, double v) {
        const double angle = 2 * kPi * (column % p.segments) / p.segments;
        const double dx = -std::sin(angle), dz = -std::cos(angle);  // outward, u = 0 at −z
        mesh.positions.push_back({static_cast<float>(radius * dx), static_cast<float>(y),
                                  static_cast<float>(radius * dz)});
        if (bottom) {
            mesh.normals.push_back({0.0f, -1.0f, 0.0f});
        } else {
            const double norm = std::sqrt(1 + slope * slope);
            mesh.normals.push_back({static_cast<float>(dx / norm),
                                    static_cast<float>(-slope / norm),
                                    static_cast<float>(dz / norm)});
        }
        mesh.uvs.push_back({static_cast<float>(u), static_cast<float>(v)});
    };
    const auto ringStart = [&](int ring) {  // ring 0: the bottom's first ring around the pole
        return static_cast<std::uint32_t>(p.segments) + static_cast<std::uint32_t>(ring) * columns;
    };

    // The bottom: one pole vertex per segment (each with its own u), then rings outwards.
    for (int i = 0; i < p.segments; ++i) {
        addVertex(0, 0.0, 0.0, 0.0, true, (i + 0.5) / p.segments, 0.0);
    }
    for (int k = 1; k <= p.baseRings; ++k) {
        // The outermost ring must meet the side's first ring exactly.
        const double radius = k == p.baseRings ? footRadius : footRadius * k / p.baseRings;
        for (int i = 0; i <= p.segments; ++i) {
            addVertex(i, radius, 0.0, 0.0, true, static_cast<double>(i) / p.segments,
                      radius / totalArc);
        }
    }
    // The side, rings evenly spaced in arc length from the foot to the lip.
    for (int j = 0; j <= p.rings; ++j) {
        const double along = arc.length() * j / p.rings;
        const double y = j == p.rings ? p.height : arc.heightAt(along);
        const double radius = j == 0 ? footRadius : vaseRadius(y, p.height);
        for (int i = 0; i <= p.segments; ++i) {
            addVertex(i, radius, y, vaseRadiusSlope(y, p.height), false,
                      static_cast<double>(i) / p.segments,
                      j == p.rings ? 1.0 : (footRadius + along) / totalArc);
        }
    }

    // Quads (a, b, c, d) = (i, k), (i+1, k), (i+1, k+1), (i, k+1) with u along i and v along
    // k: ∂p/∂u × ∂p/∂v points outward, so (a, b, c) and (a, c, d) are counter-clockwise seen
    // from outside.
    const auto quad = [&](std::uint32_t lower, std::uint32_t upper, std::uint32_t i) {
        const std::uint32_t a = lower + i, b = lower + i + 1, c = upper + i + 1, d = upper + i;
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    };
    for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(p.segments); ++i) {
        mesh.indices.insert(mesh.indices.end(), {i, ringStart(0) + i + 1, ringStart(0) + i});
    }
    for (int k = 0; k + 1 < p.baseRings; ++k) {
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(p.segments); ++i) {
            quad(ringStart(k), ringStart(k + 1), i);
        }
    }
    for (int j = 0; j < p.rings; ++j) {
        for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(p.segments); ++i) {
            quad(ringStart(p.baseRings + j), ringStart(p.baseRings + j + 1), i);
        }
    }
    return mesh;
}

}  // namespace vpe::scene
