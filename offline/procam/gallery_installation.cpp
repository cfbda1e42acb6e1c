// SPDX-License-Identifier: MIT
// The simulated gallery: where everything stands, and the truth of it.
#include "vpe/procam/gallery_installation.h"

#include <cmath>

#include "vpe/common/input_error.h"
#include "vpe/scene/procedural_vase.h"

namespace vpe::procam {

namespace {

using renderer::procam::CheckerBoard;
using renderer::procam::ProcamScene;
using renderer::procam::RigidPose;
using renderer::procam::rotationAbout;
using Vec3d = proto::Vec3d;

constexpr double kPi = 3.14159265358979323846;

// Deterministic uniforms in [0, 1) from a seed and a counter (SplitMix64).
double uniform(std::uint64_t seed, std::uint64_t counter) {
    std::uint64_t x = seed * 0x9E3779B97F4A7C15ull + counter + 0x632BE59BD9B4E019ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    x ^= x >> 31;
    return static_cast<double>(x >> 11) * 0x1.0p-53;
}

std::array<double, 9> multiply(const std::array<double, 9>& a, const std::array<double, 9>& b) {
    std::array<double, 9> out{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                out[static_cast<std::size_t>(3 * i + j)] +=
                    a[static_cast<std::size_t>(3 * i + k)] * b[static_cast<std::size_t>(3 * k + j)];
            }
        }
    }
    return out;
}

// A device at `eye` whose image centre sees `target`, with its principal point at (cx, cy):
// the optical axis is turned by the lens shift so that the picture, not the axis, is centred.
proto::PinholeCamera deviceSeeing(int width, int height, double focal, double cx, double cy,
                                  const std::array<double, 5>& distortion, const Vec3d& eye,
                                  const Vec3d& target) {
    proto::PinholeCamera device = proto::cameraLookingAt(width, height, 30.0, eye, target);
    const double shiftX = (0.5 * (width - 1) - cx) / focal;
    const double shiftY = (0.5 * (height - 1) - cy) / focal;
    // Rotations about the device's own y and x axes carry the target from the axis to the
    // normalized position of the image centre.
    const std::array<double, 9> turn =
        multiply(rotationAbout({1, 0, 0}, -std::atan(shiftY) * 180 / kPi),
                 rotationAbout({0, 1, 0}, std::atan(shiftX) * 180 / kPi));
    device.R = multiply(turn, device.R);
    for (std::size_t i = 0; i < 3; ++i) {
        device.T[i] =
            -(device.R[3 * i] * eye.x + device.R[3 * i + 1] * eye.y + device.R[3 * i + 2] * eye.z);
    }
    device.K = {focal, 0, cx, 0, focal, cy, 0, 0, 1};
    device.distortion = distortion;
    return device;
}

}  // namespace

renderer::procam::ScreenObject screenObjectOf(const scene::ScreenMesh& mesh,
                                              const RigidPose& pose) {
    renderer::procam::ScreenObject object;
    object.positions = mesh.positions;
    object.normals = mesh.normals;
    object.uvs = mesh.uvs;
    object.indices = mesh.indices;
    object.pose = pose;
    return object;
}

GalleryInstallation makeGalleryInstallation(const GalleryOptions& options) {
    const auto checkSize = [](int width, int height, const char* what) {
        if (width < 8 || height < 8 || width > 8192 || height > 8192) {
            throw common::InputError(std::string(what) + " size " + std::to_string(width) + "x" +
                                     std::to_string(height) + " is outside 8..8192");
        }
    };
    checkSize(options.projectorWidth, options.projectorHeight, "projector");
    checkSize(options.cameraWidth, options.cameraHeight, "camera");
    if ((options.boardPoses != 0 && options.boardPoses < 3) || options.boardPoses > 64) {
        throw common::InputError("board poses: " + std::to_string(options.boardPoses) +
                                 " (a calibration needs 3..64)");
    }
    GalleryInstallation gallery;
    gallery.object = scene::makeProceduralVase();
    const Vec3d centre{0, 0.075, 0};  // the vase's middle, where the devices aim

    // The object: turned about its axis, leaning a little, off the plinth's centre.
    const std::uint64_t seed = options.seed;
    const double turn = 360 * uniform(seed, 1);
    const double leanAzimuth = 2 * kPi * uniform(seed, 2);
    const double lean = 1.0 + 2.0 * uniform(seed, 3);
    RigidPose pose;
    pose.R = multiply(rotationAbout({std::cos(leanAzimuth), 0, std::sin(leanAzimuth)}, lean),
                      rotationAbout({0, 1, 0}, turn));
    pose.t = {0.03 * (uniform(seed, 4) - 0.5), 0.0, 0.03 * (uniform(seed, 5) - 0.5)};
    gallery.objectPose = pose;

    // The projector: not the demo's — 26° vertical field, lens shift upwards (principal point
    // 12% below the centre), barrel distortion, per-channel gammas, a black level, defocus.
    const int pw = options.projectorWidth, ph = options.projectorHeight;
    const double projectorFocal = 0.5 * ph / std::tan(13.0 * kPi / 180);
    ProcamScene room;
    room.projector.camera =
        deviceSeeing(pw, ph, projectorFocal, 0.5 * (pw - 1) + 0.01 * pw, 0.5 * (ph - 1) + 0.12 * ph,
                     {-0.035, 0.012, 0.0004, -0.0002, 0}, {0.05, 0.11, 0.61}, centre);
    room.projector.response = proto::ResponseFunction::gamma({2.2, 2.25, 2.15});
    room.projector.blackLevel = {0.003, 0.003, 0.004};
    room.projector.peakIrradiance = 1.0;
    room.projector.blurPixels = 0.7 * pw / 1920.0 + 0.3;
    room.room.ambient = {options.roomLight, options.roomLight, 0.92 * options.roomLight};
    room.room.interreflection = true;
    room.room.interreflectionGrid = 48;
    if (options.stains || options.realisticLight) {
        room.albedo.footShade = 0.15;
        room.albedo.stainStrength = 0.25;
        room.albedo.seed = seed;
    }
    if (options.realisticLight) {
        // Stains take up to 46 % of the albedo: 0.54..1 of the base, ±30 % about the middle.
        room.albedo.stainStrength = 0.46;
        room.albedo.footShade = 0.1;
        // Curves with a toe and a shoulder: a mix of a steep power and a smoothstep, weighted
        // differently per channel, so no single gamma fits any of them.
        std::array<std::vector<double>, 3> curves;
        std::vector<double> levels;
        const double power[3] = {2.6, 2.3, 2.8}, share[3] = {0.35, 0.2, 0.45};
        for (int i = 0; i <= 64; ++i) {
            const double v = i / 64.0;
            levels.push_back(v);
            for (std::size_t c = 0; c < 3; ++c) {
                curves[c].push_back((1 - share[c]) * std::pow(v, power[c]) +
                                    share[c] * v * v * (3 - 2 * v));
            }
        }
        room.projector.response = proto::ResponseFunction::sampled(levels, curves);
        room.projector.mixing = {0.92, 0.07, 0.01, 0.06, 0.88, 0.05, 0.01, 0.09, 0.93};
        if (options.uniformPlaster) {
            room.albedo.stainStrength = 0;
            room.albedo.footShade = 0;
        }
        // 2 % of full white at the object's centre, at normal incidence.
        const Vec3d p = room.projector.camera.center();
        const double d2 = (p.x - centre.x) * (p.x - centre.x) +
                          (p.y - centre.y) * (p.y - centre.y) + (p.z - centre.z) * (p.z - centre.z);
        const double ambient = 0.02 * room.projector.peakIrradiance / d2;
        room.room.ambient = {ambient, ambient, 0.92 * ambient};
    }

    // The camera: a Raspberry Pi camera (IMX219) in its 2×2-binned raw mode, to the projector's
    // left (21 cm by default), 4 cm higher and 3 cm nearer the object.
    const int cw = options.cameraWidth, chh = options.cameraHeight;
    const double cameraFocal = 1360.0 * cw / 1640.0;
    renderer::procam::SimulatedCamera& camera = gallery.camera;
    camera.camera =
        deviceSeeing(cw, chh, cameraFocal, 0.5 * (cw - 1) + 7.0 * cw / 1640.0,
                     0.5 * (chh - 1) - 5.0 * chh / 1232.0, {0.085, -0.16, 0.0006, -0.0004, 0},
                     {0.05 - options.cameraOffsetM, 0.15, 0.58}, centre);
    camera.response = renderer::procam::CameraResponse::kLinear;
    camera.bits = 10;
    camera.exposure = options.exposure;
    camera.fullWellElectrons = options.noise ? 10000 : 0;
    camera.readNoiseElectrons = options.noise ? 5 : 0;
    camera.blackLevel = options.cameraBlack;
    camera.samples = 2;
    camera.monochrome = true;
    camera.seed = seed;

    gallery.objectScene = room;
    gallery.objectScene.object = screenObjectOf(gallery.object, pose);

    // The boards: a 10 × 7 board of 18 mm squares held at poses spread over what both devices
    // see, tilted up to 30° each way, nearer and further — inside the projector's light, as the
    // technician holds it (docs/install.md): a pose whose board would leave the projector's image
    // (with a 4% margin) is brought in towards the middle until it fits.
    CheckerBoard board;
    board.squaresX = 10;
    board.squaresY = 7;
    board.squareM = 0.018;
    board.marginM = 0.018;  // a quiet zone of one square, as printed boards have
    gallery.board = board;
    const Vec3d boardCentre{(board.squaresX - 2) * board.squareM / 2,
                            (board.squaresY - 2) * board.squareM / 2, 0};
    // Board x → room +x, y → room −y (rows downwards), z → room −z (printed face to the devices).
    const std::array<double, 9> facing{1, 0, 0, 0, -1, 0, 0, 0, -1};
    const proto::PinholeCamera& projector = room.projector.camera;
    const auto insideProjector = [&](const CheckerBoard& b) {
        const double x0 = -b.squareM - b.marginM, y0 = x0;
        const double x1 = (b.squaresX - 1) * b.squareM + b.marginM;
        const double y1 = (b.squaresY - 1) * b.squareM + b.marginM;
        for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) {
            const auto pixel = proto::projectToPixel(projector, b.pose.apply({x, y, 0}));
            if (!pixel || pixel->x < 0.04 * pw || pixel->x > 0.96 * pw || pixel->y < 0.04 * ph ||
                pixel->y > 0.96 * ph) {
                return false;
            }
        }
        return true;
    };
    for (int k = 0; k < options.boardPoses; ++k) {
        // Spread over the projector's field (a 3 × 3 walk), three depths, and tilts that turn
        // the board towards each side in turn: what constrains the lenses and the pair.
        const int column = k % 3 - 1, row = (k / 3) % 3 - 1, depth = (k * 2) % 3 - 1;
        const double turnSign = k % 2 == 0 ? 1 : -1;
        CheckerBoard posed = board;
        for (double reach = 1.0; reach > 0.05; reach *= 0.85) {
            const double yaw =
                reach * (-column * 22 + turnSign * 10 + 4 * (uniform(seed, 100 + k) - 0.5));
            const double pitch =
                reach * (row * 18 - turnSign * 8 + 4 * (uniform(seed, 200 + k) - 0.5));
            const double roll = reach * 10 * std::sin(2.3 * k + 0.5);
            const Vec3d at{centre.x + reach * 0.09 * column, centre.y - reach * 0.045 * row,
                           centre.z + 0.07 * depth};
            posed.pose.R =
                multiply(multiply(rotationAbout({0, 1, 0}, yaw), rotationAbout({1, 0, 0}, pitch)),
                         multiply(rotationAbout({0, 0, 1}, roll), facing));
            const Vec3d offset = posed.pose.rotate(boardCentre);
            posed.pose.t = {at.x - offset.x, at.y - offset.y, at.z - offset.z};
            if (insideProjector(posed)) {
                break;
            }
        }
        ProcamScene scene = room;
        scene.room.interreflection = false;  // a flat board does not light itself
        scene.board = posed;
        gallery.boardScenes.push_back(scene);
    }
    return gallery;
}

}  // namespace vpe::procam
