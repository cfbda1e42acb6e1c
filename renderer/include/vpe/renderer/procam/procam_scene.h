// SPDX-License-Identifier: MIT
// ProcamScene: a simulated installation — the white object at a pose in the room, an optional
// printed checkerboard, a projector and a room — and the camera that photographs it. Plain
// data with the truth in it: what the simulator renders and what every install test checks
// against (renderer/procam/README.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/response_function.h"
#include "vpe/renderer/cpu/render_mesh.h"
#include "vpe/renderer/procam/dlp_timing.h"

namespace vpe::renderer::procam {

// X_room = R·X + t for X in the frame it places (metres, R row-major).
struct RigidPose {
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::array<double, 3> t{};

    Vec3d apply(const Vec3d& point) const;
    Vec3d rotate(const Vec3d& direction) const;
    RigidPose inverse() const;
    // (this ∘ inner)(X) = this(inner(X)).
    RigidPose compose(const RigidPose& inner) const;
};

// A rotation of `degrees` about `axis` (need not be unit length), and the pose that puts a
// frame's origin at `position` with its axes rotated so.
std::array<double, 9> rotationAbout(const Vec3d& axis, double degrees);
// The angle of a rotation matrix, in degrees.
double rotationAngleDegrees(const std::array<double, 9>& R);

// The white object: its mesh in its own frame (metres; normals outward; OBJ uvs, v up) and
// where it stands.
struct ScreenObject {
    std::vector<Vec3f> positions, normals;
    std::vector<Vec2f> uvs;
    std::vector<std::uint32_t> indices;
    RigidPose pose;  // object frame → room

    RenderMesh view() const { return {positions, normals, uvs, indices}; }
};

// The plaster's diffuse albedo: `base` (linear RGB) darkened towards the foot by `footShade`
// (0: none; 0.2: 20% darker at the lowest point of the object, fading out by its middle) and
// by stains — smooth value noise over the surface, `stainScale` metres across, taking up to
// `stainStrength` of the albedo (0: none). Deterministic in `seed`.
struct PlasterAlbedo {
    std::array<double, 3> base{0.85, 0.85, 0.85};
    double footShade = 0.0;
    double stainStrength = 0.0;
    double stainScale = 0.02;
    std::uint64_t seed = 1;
};

// A printed checkerboard on a flat rigid plate (the calibration target). Board frame: origin at
// the first inner corner, x along the columns, y along the rows, z into the plate (the printed
// face looks towards −z): OpenCV's object points (i·square, j·square, 0) for inner corner
// (i, j). Square (c, r) — c in [0, squaresX), r in [0, squaresY) — covers
// x ∈ [(c − 1)·square, c·square], y likewise, and is dark when c + r is even. A white margin
// surrounds the squares.
struct CheckerBoard {
    int squaresX = 10, squaresY = 7;  // inner corners: 9 × 6
    double squareM = 0.02;
    double marginM = 0.015;
    std::array<double, 3> light{0.80, 0.80, 0.80};  // paper
    std::array<double, 3> dark{0.04, 0.04, 0.04};   // toner
    RigidPose pose;                                 // board frame → room

    int cornersX() const { return squaresX - 1; }
    int cornersY() const { return squaresY - 1; }
    // Inner corner (i, j) in the room.
    Vec3d corner(int i, int j) const;
};

// The projector: its camera model (room → projector), how a drive level becomes light, how
// much light, and how sharp.
struct SimulatedProjector {
    proto::PinholeCamera camera;
    // Relative output per channel: black + (1 − black)·response(level). The black level is the
    // light a projector leaks at level 0 (a fraction of full output).
    proto::ResponseFunction response = proto::ResponseFunction::gamma(2.2);
    std::array<double, 3> blackLevel{0.002, 0.002, 0.002};
    // Crosstalk between the primaries, row-major: the light in channel k is
    // Σ_c mixing[3k + c] · output_c. Identity: each primary lights its own channel alone. A real
    // projector's colour wheel or LCD filters leak: its red carries some green, and so on.
    std::array<double, 9> mixing{1, 0, 0, 0, 1, 0, 0, 0, 1};
    // Irradiance on a surface 1 m away at normal incidence, full white.
    double peakIrradiance = 1.0;
    // Defocus: the light of each pixel spread by a Gaussian of this σ (projector pixels) on top
    // of the pixel's own footprint; 0 keeps pixels sharp.
    double blurPixels = 0.7;
    // A DLP's bit-planes against the camera's exposure (dlp_timing.h): off by default, every
    // capture sees each level's time-average.
    DlpTiming dlp;
};

enum class CameraResponse : std::uint8_t {
    kLinear,  // raw sensor values
    kGamma,   // value = signal^(1/γ), as an ISP's YUV output
};

// The camera: its model (room → camera) and its sensor. A pixel's signal is
// exposure × radiance (1 = full well), averaged over samples² points of the pixel's area;
// then shot noise (Poisson in electrons, full well = fullWellElectrons) and read noise, the
// black level, the response, and quantization to `bits`.
struct SimulatedCamera {
    proto::PinholeCamera camera;
    double exposure = 1.0;
    CameraResponse response = CameraResponse::kLinear;
    double gamma = 2.2;
    double fullWellElectrons = 6000;  // 0: no shot noise
    double readNoiseElectrons = 4;    // σ; 0: none
    int bits = 8;                     // 8 or 10
    int samples = 2;                  // per axis and pixel
    bool monochrome = true;           // one channel (Rec. 709 luminance of the light), or RGB
    std::uint64_t seed = 1;
    // The sensor's black level (pedestal): an offset every value carries whatever the light, as
    // a share of full scale; a raw frame with the lens capped reads it.
    double blackLevel = 0;
};

struct Room {
    // Irradiance the room's own lights put on every surface, in the projector's units.
    std::array<double, 3> ambient{0, 0, 0};
    // One bounce of the projector's (and the room's) light from the object onto itself.
    bool interreflection = true;
    int interreflectionGrid = 48;  // patches along u and v of the object's texture space
};

struct ProcamScene {
    std::optional<ScreenObject> object;
    PlasterAlbedo albedo;
    std::optional<CheckerBoard> board;
    SimulatedProjector projector;
    Room room;
};

// Why the scene or camera cannot be simulated, as a phrase; "" when they can.
std::string checkProcamScene(const ProcamScene& scene);
std::string checkSimulatedCamera(const SimulatedCamera& camera);

// The albedo at an object point (object frame) whose lowest and highest heights (object y) are
// `yRange`.
std::array<double, 3> plasterAlbedoAt(const PlasterAlbedo& albedo, const Vec3d& objectPoint,
                                      const std::array<double, 2>& yRange);

}  // namespace vpe::renderer::procam
