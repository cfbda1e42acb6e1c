// SPDX-License-Identifier: MIT
// The reference lights and the level comparison (see the header).
#include "support/reference_lights.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

namespace vpe::testing {

namespace {

constexpr ReferenceLight kLights[] = {
    {"key", {0.3, 0.4, 0.6}},      {"left", {-0.4, 0.2, 0.5}},    {"front", {0.0, 0.1, 0.8}},
    {"low", {0.5, -0.1, 0.3}},     {"side", {0.6, 0.1, 0.0}},     {"over", {0.0, 0.42, -0.38}},
    {"under", {0.0, -0.4, -0.38}}, {"behind", {0.15, 0.2, -0.6}},
};

int level8(double level) {
    return static_cast<int>(std::lround(std::clamp(level, 0.0, 1.0) * 255.0));
}

}  // namespace

std::span<const ReferenceLight> referenceLights() {
    return kLights;
}

GrazingShare grazingShare(const proto::BundleView& bundle, const renderer::Vec3d& light) {
    using renderer::Vec3d;
    const proto::ProjectorCalibration& p = bundle.projector();
    // The projector's centre in the object frame: −Rᵀ·T.
    const Vec3d projector{-(p.rotation[0] * p.translation[0] + p.rotation[3] * p.translation[1] +
                            p.rotation[6] * p.translation[2]),
                          -(p.rotation[1] * p.translation[0] + p.rotation[4] * p.translation[1] +
                            p.rotation[7] * p.translation[2]),
                          -(p.rotation[2] * p.translation[0] + p.rotation[5] * p.translation[1] +
                            p.rotation[8] * p.translation[2])};
    const auto& v = bundle.settings().viewerPosition;
    const Vec3d viewer{v[0], v[1], v[2]};
    const double sine = std::sin(kGrazingDegrees * 3.14159265358979323846 / 180.0);
    const proto::MeshView& mesh = bundle.mesh();
    std::size_t seen = 0, lit = 0, grazing = 0;
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        const Vec3d x{mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]};
        const Vec3d n{mesh.normals[3 * i], mesh.normals[3 * i + 1], mesh.normals[3 * i + 2]};
        const auto toward = [&](const Vec3d& target) {
            return proto::normalized(Vec3d{target.x - x.x, target.y - x.y, target.z - x.z});
        };
        if (proto::dot(n, toward(projector)) <= 0 || proto::dot(n, toward(viewer)) <= 0) {
            continue;
        }
        ++seen;
        const double elevation = proto::dot(n, toward(light));
        lit += elevation > 0 ? 1 : 0;
        grazing += elevation > 0 && elevation <= sine ? 1 : 0;
    }
    GrazingShare share;
    share.lit = seen > 0 ? static_cast<double>(lit) / static_cast<double>(seen) : 0.0;
    share.grazing = lit > 0 ? static_cast<double>(grazing) / static_cast<double>(lit) : 0.0;
    return share;
}

namespace {

template <typename Level>
LevelError compare(const renderer::ProjectorFrame& reference, Level&& level) {
    LevelError error;
    error.frameCount = 3 * reference.coverage.values.size();
    for (std::size_t p = 0; p < reference.coverage.values.size(); ++p) {
        for (std::size_t c = 0; c < 3; ++c) {
            const double a = reference.level.values[3 * p + c];
            const double b = level(p, c);
            const int d8 = level8(a) - level8(b);
            error.largest8 = std::max(error.largest8, std::abs(d8));
            error.squared8Frame += static_cast<double>(d8) * d8;
            if (reference.coverage.values[p]) {
                error.squared8 += static_cast<double>(d8) * d8;
                error.squaredLevels += (a - b) * (a - b);
                ++error.count;
            }
        }
    }
    return error;
}

}  // namespace

LevelError levelError(const renderer::ProjectorFrame& reference, std::span<const float> levels) {
    return compare(reference, [&](std::size_t p, std::size_t c) {
        return static_cast<double>(levels[3 * p + c]);
    });
}

LevelError levelError(const renderer::ProjectorFrame& reference,
                      std::span<const std::uint8_t> rgba) {
    return compare(reference, [&](std::size_t p, std::size_t c) {
        return static_cast<double>(rgba[4 * p + c]) / 255.0;
    });
}

double psnr(double squared, std::size_t count, double peak) {
    const double mse = squared / static_cast<double>(std::max<std::size_t>(count, 1));
    return mse > 0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
}

}  // namespace vpe::testing
