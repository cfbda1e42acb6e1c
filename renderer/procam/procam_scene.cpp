// SPDX-License-Identifier: MIT
// Poses, the checkerboard's corners, the plaster's albedo and the scene's checks.
#include "vpe/renderer/procam/procam_scene.h"

#include <algorithm>
#include <cmath>

#include "vector_math.h"

namespace vpe::renderer::procam {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A hash of integer lattice coordinates to [0, 1): the value noise's random values.
double latticeValue(std::int64_t x, std::int64_t y, std::int64_t z, std::uint64_t seed) {
    std::uint64_t h = seed * 0x9E3779B97F4A7C15ull;
    for (const std::int64_t v : {x, y, z}) {
        h ^= static_cast<std::uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// Trilinear value noise with a smoothstep fade, in [0, 1].
double valueNoise(const Vec3d& p, std::uint64_t seed) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy),
               iz = static_cast<std::int64_t>(fz);
    const auto fade = [](double t) { return t * t * (3 - 2 * t); };
    const double tx = fade(p.x - fx), ty = fade(p.y - fy), tz = fade(p.z - fz);
    double value = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
        const double weight = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty) * (dz ? tz : 1 - tz);
        value += weight * latticeValue(ix + dx, iy + dy, iz + dz, seed);
    }
    return value;
}

bool finiteAll(const auto& values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

Vec3d RigidPose::apply(const Vec3d& p) const {
    return rotate(p) + Vec3d{t[0], t[1], t[2]};
}

Vec3d RigidPose::rotate(const Vec3d& d) const {
    return {R[0] * d.x + R[1] * d.y + R[2] * d.z, R[3] * d.x + R[4] * d.y + R[5] * d.z,
            R[6] * d.x + R[7] * d.y + R[8] * d.z};
}

RigidPose RigidPose::inverse() const {
    RigidPose out;
    out.R = {R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]};
    const Vec3d back = out.rotate({t[0], t[1], t[2]});
    out.t = {-back.x, -back.y, -back.z};
    return out;
}

RigidPose RigidPose::compose(const RigidPose& inner) const {
    RigidPose out;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double sum = 0;
            for (int k = 0; k < 3; ++k) {
                sum += R[static_cast<std::size_t>(3 * i + k)] *
                       inner.R[static_cast<std::size_t>(3 * k + j)];
            }
            out.R[static_cast<std::size_t>(3 * i + j)] = sum;
        }
    }
    const Vec3d moved = apply({inner.t[0], inner.t[1], inner.t[2]});
    out.t = {moved.x, moved.y, moved.z};
    return out;
}

std::array<double, 9> rotationAbout(const Vec3d& axis, double degrees) {
    const double norm = length(axis);
    if (!(norm > 0) || degrees == 0) {
        return {1, 0, 0, 0, 1, 0, 0, 0, 1};
    }
    const double x = axis.x / norm, y = axis.y / norm, z = axis.z / norm;
    const double angle = degrees * kPi / 180;
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
            t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
            t * x * z - s * y, t * y * z + s * x, t * z * z + c};
}

double rotationAngleDegrees(const std::array<double, 9>& R) {
    const double cosine = std::clamp((R[0] + R[4] + R[8] - 1) / 2, -1.0, 1.0);
    // acos loses precision near 0: the sine from the skew part is exact there.
    const double sine =
        0.5 * std::sqrt((R[7] - R[5]) * (R[7] - R[5]) + (R[2] - R[6]) * (R[2] - R[6]) +
                        (R[3] - R[1]) * (R[3] - R[1]));
    return std::atan2(sine, cosine) * 180 / kPi;
}

Vec3d CheckerBoard::corner(int i, int j) const {
    return pose.apply({i * squareM, j * squareM, 0});
}

std::array<double, 3> plasterAlbedoAt(const PlasterAlbedo& albedo, const Vec3d& p,
                                      const std::array<double, 2>& yRange) {
    double factor = 1;
    if (albedo.footShade > 0 && yRange[1] > yRange[0]) {
        // Fades from the foot to the middle of the object's height.
        const double height = (p.y - yRange[0]) / (0.5 * (yRange[1] - yRange[0]));
        factor *= 1 - albedo.footShade * std::clamp(1 - height, 0.0, 1.0);
    }
    if (albedo.stainStrength > 0) {
        const double scale = 1 / albedo.stainScale;
        // Two octaves; stains are where the noise is high, their edges soft.
        const double n = 0.65 * valueNoise(scale * p, albedo.seed) +
                         0.35 * valueNoise(2.7 * scale * p, albedo.seed + 1);
        const double stain = std::clamp((n - 0.55) / 0.2, 0.0, 1.0);
        factor *= 1 - albedo.stainStrength * stain;
    }
    return {albedo.base[0] * factor, albedo.base[1] * factor, albedo.base[2] * factor};
}

std::string checkProcamScene(const ProcamScene& scene) {
    if (!scene.object && !scene.board) {
        return "the scene has neither an object nor a checkerboard";
    }
    if (scene.object) {
        const ScreenObject& o = *scene.object;
        if (auto problem = checkRenderMesh(o.view()); !problem.empty()) {
            return "object: " + problem;
        }
        if (!finiteAll(o.pose.R) || !finiteAll(o.pose.t)) {
            return "object: pose is not finite";
        }
    }
    if (scene.board) {
        const CheckerBoard& b = *scene.board;
        if (b.squaresX < 3 || b.squaresY < 3 || b.squaresX > 64 || b.squaresY > 64) {
            return "board: squares must be 3..64 along each side";
        }
        if (!(b.squareM > 0) || !(b.marginM >= 0) || !std::isfinite(b.squareM + b.marginM)) {
            return "board: square size must be positive and the margin ≥ 0";
        }
    }
    const SimulatedProjector& p = scene.projector;
    if (auto problem = proto::checkCamera(p.camera); !problem.empty()) {
        return "projector: " + problem;
    }
    for (const double black : p.blackLevel) {
        if (!(black >= 0 && black < 1)) {
            return "projector: black level must be in [0, 1)";
        }
    }
    for (const double m : p.mixing) {
        if (!(m >= 0 && m <= 1)) {
            return "projector: mixing must be 9 numbers in [0, 1]";
        }
    }
    if (!(p.peakIrradiance > 0) || !std::isfinite(p.peakIrradiance)) {
        return "projector: peak irradiance must be positive";
    }
    if (!(p.blurPixels >= 0 && p.blurPixels <= 20)) {
        return "projector: blur must be in [0, 20] pixels";
    }
    if (!(p.dlp.exposureFrames >= 0 && p.dlp.exposureFrames <= 100)) {
        return "projector: the DLP exposure must be in [0, 100] frames (0: off)";
    }
    for (const double a : scene.room.ambient) {
        if (!(a >= 0) || !std::isfinite(a)) {
            return "room: ambient must be finite and ≥ 0";
        }
    }
    if (scene.room.interreflectionGrid < 4 || scene.room.interreflectionGrid > 256) {
        return "room: interreflection grid must be 4..256";
    }
    for (const double a : scene.albedo.base) {
        if (!(a > 0 && a <= 1)) {
            return "albedo: base must be in (0, 1]";
        }
    }
    if (!(scene.albedo.footShade >= 0 && scene.albedo.footShade < 1) ||
        !(scene.albedo.stainStrength >= 0 && scene.albedo.stainStrength < 1) ||
        !(scene.albedo.stainScale > 0)) {
        return "albedo: foot shade and stain strength in [0, 1), stain scale > 0";
    }
    return "";
}

std::string checkSimulatedCamera(const SimulatedCamera& c) {
    if (auto problem = proto::checkCamera(c.camera); !problem.empty()) {
        return "camera: " + problem;
    }
    if (!(c.exposure > 0) || !std::isfinite(c.exposure)) {
        return "camera: exposure must be positive";
    }
    if (c.response == CameraResponse::kGamma && !(c.gamma > 0 && c.gamma < 10)) {
        return "camera: gamma must be in (0, 10)";
    }
    if (!(c.fullWellElectrons >= 0) || !(c.readNoiseElectrons >= 0) ||
        !std::isfinite(c.fullWellElectrons + c.readNoiseElectrons)) {
        return "camera: full well and read noise must be ≥ 0";
    }
    if (c.readNoiseElectrons > 0 && !(c.fullWellElectrons > 0)) {
        return "camera: read noise needs a full well to be measured against";
    }
    if (!(c.blackLevel >= 0 && c.blackLevel < 0.5)) {
        return "camera: black level must be in [0, 0.5)";
    }
    if (c.bits != 8 && c.bits != 10) {
        return "camera: bits must be 8 or 10";
    }
    if (c.samples < 1 || c.samples > 8) {
        return "camera: samples per axis must be 1..8";
    }
    return "";
}

}  // namespace vpe::renderer::procam
