// SPDX-License-Identifier: MIT
// Writes small captures whose truth is known exactly: every pixel's images are rendered from
// given Fourier coefficients through proto's evaluator, so a fit can be checked to rounding.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/geometry_calibration.h"
#include "vpe/normals/normal_map.h"

namespace vpe::testing {

enum class SyntheticFormat {
    kExr,          // float, linear: exact
    kPng16Linear,  // 16-bit linear PNG
    kPng8Srgb,     // 8-bit sRGB PNG
    kPng8Linear,   // 8-bit PNG storing radiance linearly (many RTI cameras' JPEGs)
};

struct SyntheticCaptureSpec {
    int width = 24;
    int height = 16;
    int harmonics = 3;
    std::vector<proto::Vec3d> lights;  // unit directions; default: a full sphere of 64 lights
    SyntheticFormat format = SyntheticFormat::kExr;
    // Normal of pixel (x, y); default: a gentle dome facing the camera.
    std::function<proto::Vec3d(int x, int y)> normal;
    // Writes 2M + 2 coefficients of pixel (x, y), channel c; default: seeded random values
    // around a plausible diffuse + specular material.
    std::function<void(int x, int y, int c, double* coefficients)> coefficients;
    std::uint32_t seed = 1;
    // capture.json with float normals (exact) instead of dirs.lp + 16-bit normals.png.
    bool manifest = true;
    // Render under this camera and light geometry while the .lp still states directions
    // (what a real dome's light file does); identity = orthographic and directional.
    capture::GeometryCalibration geometry;
    // Multiplies the rendering of pixel (x, y) under a light direction: cast shadows.
    std::function<double(int x, int y, const proto::Vec3d& light)> transport;
    // Multiplies channel c of that rendering too: light reaching the pixel off a coloured
    // neighbour.
    std::function<double(int x, int y, int c, const proto::Vec3d& light)> tint;
};

struct SyntheticCapture {
    std::filesystem::path dir;
    std::vector<double> coefficients;   // [y][x][c][k]
    std::vector<proto::Vec3d> normals;  // [y][x]
    int coefficientCount = 0;
    const double* at(int x, int y, int c, int width) const {
        return coefficients.data() +
               ((static_cast<std::size_t>(y) * width + x) * 3 + c) * coefficientCount;
    }
};

SyntheticCapture writeSyntheticCapture(const std::filesystem::path& dir,
                                       const SyntheticCaptureSpec& spec);

// The capture's true normals as a NormalMap, every pixel valid.
normals::NormalMap trueNormalMap(const SyntheticCapture& capture, int width, int height);

// Lights spread over the whole sphere (Fibonacci lattice): well-conditioned fits.
std::vector<proto::Vec3d> sphereLights(int count);
// An RTI dome: rings at the given elevations (degrees), `perRing` lights each.
std::vector<proto::Vec3d> domeLights(const std::vector<double>& elevations, int perRing,
                                     double azimuthOffsetDegrees = 0);

}  // namespace vpe::testing
