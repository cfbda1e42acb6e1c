// SPDX-License-Identifier: MIT
// The synthetic vase: ray casting, relief, streaks, materials.
#include "vpe/synth/pottery_scene.h"

#include <algorithm>
#include <cmath>

#include "vpe/common/random_bits.h"

namespace vpe::synth {

namespace {

constexpr double kCameraDistance = 4.2;
constexpr double kHalfWidth = 0.55;  // of the view at the vase's front (z ≈ 1)
constexpr double kReliefGround = 0.007;
constexpr double kReliefStreak = 0.004;
constexpr double kReliefFrequency = 18.0;
// The relief grid covers more than the visible surface (|u| ≤ 0.72, |v| ≤ 0.66) plus the
// shadow test's reach; 1024 samples give ~3 per finest relief wavelength.
constexpr int kGrid = 1024;
constexpr double kGridUMin = -1.0, kGridUMax = 1.0;
constexpr double kGridVMin = -0.9, kGridVMax = 0.9;

double smoothstep(double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

proto::Vec3d mix(const proto::Vec3d& a, const proto::Vec3d& b, double t) {
    return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}

proto::Vec3d scaled(const proto::Vec3d& v, double s) {
    return {v.x * s, v.y * s, v.z * s};
}

}  // namespace

PotteryScene::PotteryScene(int size, std::uint64_t seed)
    : size_(size),
      pattern_(common::mixBits(seed ^ 0x51)),
      relief_(common::mixBits(seed ^ 0x52)),
      albedo_(common::mixBits(seed ^ 0x53)),
      roughness_(common::mixBits(seed ^ 0x54)) {
    const double tangent = kHalfWidth / (kCameraDistance - 1.0);
    camera_.fx = camera_.fy = (size / 2.0) / tangent;
    camera_.cx = camera_.cy = (size - 1) / 2.0;
    camera_.rotation = {1, 0, 0, 0, -1, 0, 0, 0, -1};  // looking down −z, image y down
    camera_.translation = {0, 0, kCameraDistance};
    for (int k = 0; k < 3; ++k) {
        streakPhase_[k] =
            common::uniformFromBits(common::mixBits(seed * 3 + static_cast<std::uint64_t>(k)));
    }
    reliefGrid_.resize(static_cast<std::size_t>(kGrid) * kGrid);
    for (int j = 0; j < kGrid; ++j) {
        const double v = kGridVMin + (kGridVMax - kGridVMin) * j / (kGrid - 1);
        for (int i = 0; i < kGrid; ++i) {
            const double u = kGridUMin + (kGridUMax - kGridUMin) * i / (kGrid - 1);
            reliefGrid_[static_cast<std::size_t>(j) * kGrid + i] =
                static_cast<float>(reliefAt(u, v, streakAt(u, v)));
        }
    }
}

double PotteryScene::gridRelief(double u, double v) const {
    const double x = std::clamp((u - kGridUMin) / (kGridUMax - kGridUMin), 0.0, 1.0) * (kGrid - 1);
    const double y = std::clamp((v - kGridVMin) / (kGridVMax - kGridVMin), 0.0, 1.0) * (kGrid - 1);
    const int i = std::min(static_cast<int>(x), kGrid - 2);
    const int j = std::min(static_cast<int>(y), kGrid - 2);
    const double fx = x - i, fy = y - j;
    const float* row = &reliefGrid_[static_cast<std::size_t>(j) * kGrid + i];
    const double a = row[0], b = row[1], c = row[kGrid], d = row[kGrid + 1];
    const double top = a + fx * (b - a);
    const double bottom = c + fx * (d - c);
    return top + fy * (bottom - top);
}

double PotteryScene::texelMillimetres() const {
    // The front of the surface is at z = r(0) on the camera's axis; a pixel subtends 1 / fx.
    return (kCameraDistance - radius(0.0)) / camera_.fx * kMillimetresPerUnit;
}

double PotteryScene::radius(double y) const {
    return 1.0 + 0.12 * std::sin(2.2 * y + 0.4) - 0.15 * y * y;
}

double PotteryScene::radiusSlope(double y) const {
    return 0.12 * 2.2 * std::cos(2.2 * y + 0.4) - 0.3 * y;
}

// Hidasuki: a few meandering lines in three directions, where the straw burned the clay.
double PotteryScene::streakAt(double u, double v) const {
    const double angles[3] = {0.35, 1.3, -0.6};
    const double periods[3] = {0.75, 0.95, 1.15};
    double streak = 0;
    for (int k = 0; k < 3; ++k) {
        const double w = u * std::cos(angles[k]) + v * std::sin(angles[k]) +
                         0.09 * pattern_.fractal(2.0 * u + 5 * k, 2.0 * v - 3 * k, 3);
        const double cell = w / periods[k] + streakPhase_[k];
        const double distance = std::fabs(cell - std::floor(cell) - 0.5) * periods[k];
        const double width = 0.058 + 0.02 * pattern_.at(4.0 * u + 11 * k, 4.0 * v);
        streak = std::max(streak, std::exp(-(distance / width) * (distance / width)));
    }
    return streak;
}

double PotteryScene::reliefAt(double u, double v, double streak) const {
    const double amplitude = kReliefGround + (kReliefStreak - kReliefGround) * streak;
    return amplitude * relief_.fractal(kReliefFrequency * u, kReliefFrequency * v, 4);
}

void PotteryScene::shade(SurfacePoint& p) const {
    p.streak = streakAt(p.u, p.v);
    p.label = p.streak > 0.5 ? 1 : 0;
    const double t = smoothstep(0.3, 0.7, p.streak);
    const double shadeNoise = albedo_.fractal(6.0 * p.u, 6.0 * p.v, 4);
    const double speckle = albedo_.fractal(40.0 * p.u + 7, 40.0 * p.v, 2);
    const double roughNoise = roughness_.fractal(5.0 * p.u, 5.0 * p.v, 3);
    // Earthy ground: beige-brown, rough; streaks: red-brown, glossier.
    const proto::Vec3d ground =
        scaled(proto::Vec3d{0.42, 0.31, 0.20}, 1.0 + 0.18 * shadeNoise + 0.06 * speckle);
    const proto::Vec3d streak =
        scaled(proto::Vec3d{0.40, 0.10, 0.05}, 1.0 + 0.15 * shadeNoise + 0.04 * speckle);
    p.material.albedo = mix(ground, streak, t);
    p.material.roughness = (0.55 + (0.16 - 0.55) * t) * (1.0 + 0.25 * roughNoise);
    p.material.f0 = 0.035 + 0.015 * t;
}

SurfacePoint PotteryScene::surfaceAt(int x, int y) const {
    SurfacePoint p;
    const auto& r = camera_.rotation;
    const double cx = (x - camera_.cx) / camera_.fx;
    const double cy = (y - camera_.cy) / camera_.fy;
    const proto::Vec3d d = proto::normalized(proto::Vec3d{
        r[0] * cx + r[3] * cy + r[6], r[1] * cx + r[4] * cy + r[7], r[2] * cx + r[5] * cy + r[8]});
    const proto::Vec3d o = cameraCenter();
    // Outside the surface x² + z² > r(y)²: march to the first crossing, then bisect.
    auto inside = [&](double t) {
        const double px = o.x + t * d.x, py = o.y + t * d.y, pz = o.z + t * d.z;
        return px * px + pz * pz - radius(py) * radius(py);
    };
    double near = 0, far = -1;
    for (double t = kCameraDistance - 1.6; t < kCameraDistance + 1.0; t += 0.01) {
        if (inside(t) <= 0) {
            far = t;
            near = t - 0.01;
            break;
        }
    }
    if (far < 0) {
        return p;
    }
    for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (near + far);
        (inside(mid) > 0 ? near : far) = mid;
    }
    const double t = 0.5 * (near + far);
    const proto::Vec3d base{o.x + t * d.x, o.y + t * d.y, o.z + t * d.z};
    p.hit = true;
    p.u = std::atan2(base.x, base.z);
    p.v = base.y;
    const double slope = radiusSlope(p.v);
    p.baseNormal = proto::normalized(proto::Vec3d{std::sin(p.u), -slope, std::cos(p.u)});
    p.tangentU = {std::cos(p.u), 0, -std::sin(p.u)};
    p.tangentV = proto::normalized(proto::Vec3d{slope * std::sin(p.u), 1, slope * std::cos(p.u)});
    shade(p);
    p.relief = reliefAt(p.u, p.v, p.streak);
    // Shading normal from the relief's gradient per unit arc length along each tangent.
    constexpr double kStep = 1e-4;
    const double arcU = radius(p.v);
    const double arcV = std::sqrt(1 + slope * slope);
    const double dhdu =
        (reliefAt(p.u + kStep, p.v, p.streak) - reliefAt(p.u - kStep, p.v, p.streak)) /
        (2 * kStep * arcU);
    const double dhdv =
        (reliefAt(p.u, p.v + kStep, p.streak) - reliefAt(p.u, p.v - kStep, p.streak)) /
        (2 * kStep * arcV);
    p.normal =
        proto::normalized(proto::Vec3d{p.baseNormal.x - dhdu * p.tangentU.x - dhdv * p.tangentV.x,
                                       p.baseNormal.y - dhdu * p.tangentU.y - dhdv * p.tangentV.y,
                                       p.baseNormal.z - dhdu * p.tangentU.z - dhdv * p.tangentV.z});
    p.position = {base.x + p.relief * p.baseNormal.x, base.y + p.relief * p.baseNormal.y,
                  base.z + p.relief * p.baseNormal.z};
    return p;
}

bool PotteryScene::reliefShadows(const SurfacePoint& p, const proto::Vec3d& toLight) const {
    const double up = proto::dot(toLight, p.baseNormal);
    if (up <= 0) {
        return true;  // below the smooth surface's horizon
    }
    const double along = proto::dot(toLight, p.tangentU);
    const double across = proto::dot(toLight, p.tangentV);
    const double tangential = std::sqrt(along * along + across * across);
    if (tangential < 1e-6) {
        return false;
    }
    const double arcU = radius(p.v);
    const double arcV = std::sqrt(1 + radiusSlope(p.v) * radiusSlope(p.v));
    constexpr int kSteps = 32;
    constexpr double kReach = 0.12;  // a couple of relief wavelengths
    for (int i = 1; i <= kSteps; ++i) {
        const double s = kReach * i / kSteps;
        const double du = s * along / tangential;
        const double dv = s * across / tangential;
        // The ray rises with the light's elevation; the convex body falls away under it.
        const double rayHeight = p.relief + s * up / tangential + du * du / (2 * arcU);
        const double u = p.u + du / arcU;
        const double v = p.v + dv / arcV;
        if (gridRelief(u, v) > rayHeight) {
            return true;
        }
    }
    return false;
}

}  // namespace vpe::synth
