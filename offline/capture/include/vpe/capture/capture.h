// SPDX-License-Identifier: MIT
// Capture: what a set of photographs under moving light is, once its light file or manifest
// has been read: image files, lights, camera, encoding and the optional geometry inputs.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "vpe/proto/reflection_geometry.h"

namespace vpe::capture {

using Vec3d = proto::Vec3<double>;

enum class LightKind {
    kDirectional,  // a unit direction towards the light (RTI domes, .lp files)
    kPoint,        // a position; irradiance falls off with the squared distance (paper's rig)
};

// How image values map to linear radiance.
enum class ImageEncoding {
    kAuto,    // 8-bit images are sRGB, 16-bit and floating-point images are linear
    kSrgb,    // sRGB transfer function at any bit depth
    kLinear,  // values are linear radiance
    // stored = linear^(1/γ), γ = Capture::gamma: a camera response that `vpe fit --model
    // extended` calibrated from the images (integer images only).
    kGamma,
};

struct CaptureImage {
    std::filesystem::path file;  // resolved against the light file's or manifest's folder
    Vec3d light;                 // unit direction towards the light, or its position
    double intensity = 1.0;      // observations are divided by it
    int line = 0;                // where it was declared, for messages (0: not from a line)
};

// Orthographic camera looking along −z. World frame = camera frame: x right, y up in the
// image, z towards the viewer. Pixel (x, y) (row y from the top) sits at
// ((x + ½ − W/2)·pixelSize, (H/2 − y − ½)·pixelSize, 0) unless a position map says otherwise.
struct OrthographicCamera {
    double pixelSize = 1.0;
};

// Pinhole camera with OpenCV conventions: a world point X maps to camera coordinates
// R·X + t (x right, y down, z forward), then to pixel (fx·x/z + cx, fy·y/z + cy).
struct PinholeCamera {
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, world → camera
    Vec3d translation{};
    Vec3d center() const;  // camera centre in world coordinates, −Rᵀt
};

using CameraModel = std::variant<OrthographicCamera, PinholeCamera>;

// A plane standing in for the surface when no position map is given.
struct SurfacePlane {
    Vec3d point{};
    Vec3d normal{0, 0, 1};
};

enum class NormalEncoding {
    kAuto,       // integer images are (n + 1)/2, floating-point images hold n itself
    kOffsetRgb,  // RGB = (n + 1)/2 (SynthRTI, most normal maps)
    kRaw,        // the channels are the components of n
};

struct Capture {
    std::filesystem::path source;  // the .lp file or capture.json it was read from
    LightKind lightKind = LightKind::kDirectional;
    // Point lights: observations are normalized to the irradiance of a light at this distance.
    double lightReferenceDistance = 1.0;
    ImageEncoding encoding = ImageEncoding::kAuto;
    double gamma = 1.0;  // with ImageEncoding::kGamma
    CameraModel camera = OrthographicCamera{};
    std::vector<CaptureImage> images;
    std::optional<std::filesystem::path> normalMap;  // in the world frame
    NormalEncoding normalEncoding = NormalEncoding::kAuto;
    std::optional<std::filesystem::path> positionMap;  // world XYZ per pixel (floating point)
    std::optional<SurfacePlane> plane;
    std::optional<std::filesystem::path> mask;  // nonzero = use the pixel
    // The side of one pixel on the captured surface, millimetres: what gives the texture its
    // physical scale on another object (vpe quilt --size auto).
    std::optional<double> texelMm;

    bool needsSurfacePositions() const {
        return lightKind == LightKind::kPoint || std::holds_alternative<PinholeCamera>(camera);
    }
};

// The unit vector along v, or nothing when it is too short to have a direction (length
// ≤ 1e-9). Components are scaled by the largest first, so neither 1e200 (squares overflow)
// nor 1e-200 (squares underflow) turns a valid direction into a NaN or a zero one.
std::optional<Vec3d> unitDirection(const Vec3d& v);

// The held-out protocol of RTI benchmarks: every `every`-th light (positions every − 1,
// 2·every − 1, … in the capture's order, 0-based) is a test light. Returns the test lights
// (`heldOut`) or the others (training); `every` must be ≥ 2.
Capture selectHeldOutLights(const Capture& capture, int every, bool heldOut);

// The light of one image as it arrives at a surface point: the unit direction towards it and
// its irradiance (normal to the light) relative to the unit that models are normalized to.
struct IncidentLight {
    Vec3d direction;
    double irradiance = 1.0;
};

IncidentLight incidentLight(const Capture& capture, const CaptureImage& image,
                            const Vec3d& surfacePoint);

}  // namespace vpe::capture
