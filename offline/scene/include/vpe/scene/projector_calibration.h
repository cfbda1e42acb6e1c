// SPDX-License-Identifier: MIT
// ProjectorCalibration: where the projector is and how it maps rays to pixels — a pinhole
// with OpenCV's conventions and lens distortion — read from and written to the OpenCV
// FileStorage files (YAML, XML, JSON) that projector–camera calibration tools write; and the
// camera those files may hold beside it (cam_K, cam_kc).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/vector_types.h"

namespace vpe::scene {

using Vec3d = proto::Vec3d;

// A calibration file holds exactly proto's camera model (its conventions there): a point X of
// the object frame (the screen mesh's, metres) is x = R·X + T in projector coordinates, then a
// pixel after OpenCV's distortion. One type, so that the offline tools project, centre and
// aim the projector with the device's own math (proto::projectToPixel, center(),
// proto::cameraLookingAt); the checks below are offline's, stricter and with file messages.
using ProjectorCalibration = proto::PinholeCamera;

// What the command line adds to a calibration file.
struct ProjectorCalibrationOverrides {
    // The resolution, required when the file has none; must agree with the file otherwise.
    std::optional<int> width, height;
    // The resolution when neither the file nor width/height give one (vpe scan: the scan
    // manifest's projector, which the calibration then must fit anyway).
    std::optional<int> defaultWidth, defaultHeight;
    // Metres per unit of T, when the file does not say (key length_unit: m, cm or mm).
    // procam-calibration measures T in the unit of its chessboard squares: usually mm.
    std::optional<double> metresPerUnit;
};

// Reads proj_K, proj_kc (optional: no distortion), R (3×3 matrix or Rodrigues vector) and
// T — the keys of Moreno & Taubin's procam-calibration, whose R, T take camera coordinates
// to projector coordinates: a mesh scanned with the same rig is in the camera's frame, which
// is then the object frame. cam_K, cam_kc (readCameraCalibration's) and the rest are ignored.
// Or the same read from kamino410/procam-calibration's calibration_result.xml: proj_int,
// proj_dist, rotation, translation (camera → projector too); its img_shape, rms, cam_int,
// cam_dist are the camera's. The resolution comes from proj_width/proj_height or
// image_width/image_height, or the overrides. Without a unit, T is taken in metres unless
// that puts the projector over 20 m away, which is refused as a probable millimetre file.
// Throws InputError "PATH: KEY: problem" for a missing or unreadable file, a key of neither
// layout (naming it) or keys of both, missing keys, wrong shapes, non-finite numbers, focal
// lengths ≤ 0, R not a rotation (orthonormal with det +1 within 1e-3), resolution outside
// 1..8192, a unit that disagrees with the file's length_unit.
ProjectorCalibration readProjectorCalibration(const std::filesystem::path& path,
                                              const ProjectorCalibrationOverrides& overrides = {});

// Where the camera's pose comes from in readCameraCalibration.
enum class CameraPose {
    // A procam file: its object frame is the camera's own, so R = I, T = 0 (the file's R, T are
    // the projector's, camera → projector).
    kProcamOrigin,
    // A camera file (writeCameraCalibration): R, T are the camera's pose, object → camera,
    // T's unit from length_unit (none: metres, refused beyond 20 m as probable millimetres).
    kFromFile,
};

// The camera of a calibration file: cam_K, cam_kc (optional: no distortion), and its resolution
// cam_width/cam_height, required with cam_K (procam-calibration writes none; vpe's writers do);
// or kamino410's cam_int, cam_dist and img_shape (rows, cols), only as a procam file's camera.
// Nothing when the file has no cam_K. Throws InputError "PATH: KEY: problem" as
// readProjectorCalibration does (resolution 1..8192, focal lengths > 0, finite numbers, R a
// rotation).
std::optional<proto::PinholeCamera> readCameraCalibration(
    const std::filesystem::path& path, CameraPose pose = CameraPose::kProcamOrigin);

// Metres per unit of length_unit's values (m, cm, mm); nothing for another word.
std::optional<double> metresPerLengthUnit(const std::string& unit);

// Writes the same keys (plus proj_width, proj_height and length_unit: m) as YAML (.yml,
// .yaml), XML (.xml) or JSON (.json), atomically.
void writeProjectorCalibration(const ProjectorCalibration& calibration,
                               const std::filesystem::path& path);

// writeProjectorCalibration's file with the camera's keys as well (cam_K, cam_kc, cam_width,
// cam_height) when `camera` is given, and procam's stereo_error (the stereo calibration's RMS
// reprojection error, pixels) when `stereoRms` is: what readProjectorCalibration and
// readCameraCalibration read back. The object frame is the camera's, so the camera's pose must
// be R = I, T = 0 (InputError otherwise); `projector` is then the projector in the camera's
// frame.
void writeProcamCalibration(const ProjectorCalibration& projector,
                            const std::optional<proto::PinholeCamera>& camera,
                            std::optional<double> stereoRms, const std::filesystem::path& path);

// A camera alone with its pose: cam_width, cam_height, cam_K, cam_kc, R, T (object → camera)
// and length_unit: m, read back by readCameraCalibration(path, CameraPose::kFromFile).
void writeCameraCalibration(const proto::PinholeCamera& camera, const std::filesystem::path& path);

// The checks readProjectorCalibration makes; `source` names the calibration in messages.
void validateProjectorCalibration(const ProjectorCalibration& calibration,
                                  const std::filesystem::path& source);
// The same for a camera, naming cam_K and cam_kc.
void validateCameraCalibration(const proto::PinholeCamera& camera,
                               const std::filesystem::path& source);

// A distortion-free projector at `eye` aimed at `target`, image rows parallel to the
// horizontal plane (world up is +y), square pixels, principal point at the image centre.
ProjectorCalibration projectorLookingAt(int width, int height, double verticalFovDegrees,
                                        const Vec3d& eye, const Vec3d& target);

// The demo's projector: 1920 × 1080, 30° vertical field of view, on the +z side of `target`
// (by default the middle of the procedural vase) at `distance` metres, level with it.
ProjectorCalibration makeDemoProjector(double distance, const Vec3d& target = {0, 0.075, 0});

}  // namespace vpe::scene
