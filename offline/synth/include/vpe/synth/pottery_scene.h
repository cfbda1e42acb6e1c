// SPDX-License-Identifier: MIT
// PotteryScene: the built-in synthetic object — part of a vase (a surface of revolution
// about the y axis) seen from the front by a pinhole camera, with fine relief from a height
// field and a hidasuki-like pattern: meandering red-brown streaks, glossier, over an earthy,
// rougher ground, each with noise in albedo, roughness and relief. World frame: y up, the
// camera on the +z axis looking at the origin.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/common/procedural_noise.h"
#include "vpe/synth/microfacet_brdf.h"

namespace vpe::synth {

struct SurfacePoint {
    bool hit = false;
    proto::Vec3d position;    // world, relief included
    proto::Vec3d normal;      // shading normal, relief included
    proto::Vec3d baseNormal;  // of the smooth surface of revolution
    proto::Vec3d tangentU;    // around the axis
    proto::Vec3d tangentV;    // along the profile
    double u = 0;             // azimuth (radians)
    double v = 0;             // height
    double relief = 0;
    double streak = 0;  // 0 ground … 1 streak (soft edges)
    int label = 0;      // 0 ground, 1 streak
    MicrofacetMaterial material;
};

class PotteryScene {
public:
    static constexpr int kLabels = 2;
    // The scene is in units of the vase's radius (≈ 1). Physically it is a pot 20 cm across:
    // this fixes the size of a pixel on it, so that a texture made from the capture can give
    // its streaks their real width on another object (vpe quilt --size auto).
    static constexpr double kMillimetresPerUnit = 100.0;

    PotteryScene(int size, std::uint64_t seed);

    int size() const { return size_; }
    const capture::PinholeCamera& camera() const { return camera_; }
    proto::Vec3d cameraCenter() const { return camera_.center(); }
    // The side of one pixel's footprint on the surface at the image centre, where the surface
    // faces the camera, millimetres (away from the centre foreshortening widens it along u).
    double texelMillimetres() const;

    // The surface seen through pixel (x, y), or hit = false.
    SurfacePoint surfaceAt(int x, int y) const;
    // Whether the relief around p blocks light arriving from the unit direction toLight
    // (a horizon test along the light's direction in the tangent plane).
    bool reliefShadows(const SurfacePoint& p, const proto::Vec3d& toLight) const;

private:
    double radius(double y) const;
    double radiusSlope(double y) const;
    double reliefAt(double u, double v, double streak) const;
    double streakAt(double u, double v) const;
    void shade(SurfacePoint& p) const;

    double gridRelief(double u, double v) const;

    int size_;
    capture::PinholeCamera camera_;
    common::GradientNoise pattern_, relief_, albedo_, roughness_;
    double streakPhase_[3];
    // The relief sampled on a fine (u, v) grid: the shadow test marches through it instead
    // of evaluating noise at every step (30x faster renders).
    std::vector<float> reliefGrid_;
};

}  // namespace vpe::synth
