// SPDX-License-Identifier: MIT
// ProjectorCalibration: where the projector is and how it maps rays to pixels — a pinhole
// with OpenCV's conventions and lens distortion — read from and written to the OpenCV
// FileStorage files (YAML, XML, JSON) that projector–camera calibration tools write.
#pragma once

#include <filesystem>
#include <optional>

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
    // Metres per unit of T, when the file does not say (key length_unit: m, cm or mm).
    // procam-calibration measures T in the unit of its chessboard squares: usually mm.
    std::optional<double> metresPerUnit;
};

// Reads proj_K, proj_kc (optional: no distortion), R (3×3 matrix or Rodrigues vector) and
// T — the keys of Moreno & Taubin's procam-calibration, whose R, T take camera coordinates
// to projector coordinates: a mesh scanned with the same rig is in the camera's frame, which
// is then the object frame. cam_K, cam_kc and everything else are ignored. The resolution
// comes from proj_width/proj_height or image_width/image_height, or the overrides. Without
// a unit, T is taken in metres unless that puts the projector over 20 m away, which is
// refused as a probable millimetre file. Throws InputError "PATH: KEY: problem" for a
// missing or unreadable file, missing keys, wrong shapes, non-finite numbers, focal lengths
// ≤ 0, R not a rotation (orthonormal with det +1 within 1e-3), resolution outside 1..8192.
ProjectorCalibration readProjectorCalibration(const std::filesystem::path& path,
                                              const ProjectorCalibrationOverrides& overrides = {});

// Writes the same keys (plus proj_width, proj_height and length_unit: m) as YAML (.yml,
// .yaml), XML (.xml) or JSON (.json), atomically.
void writeProjectorCalibration(const ProjectorCalibration& calibration,
                               const std::filesystem::path& path);

// The checks readProjectorCalibration makes; `source` names the calibration in messages.
void validateProjectorCalibration(const ProjectorCalibration& calibration,
                                  const std::filesystem::path& source);

// A distortion-free projector at `eye` aimed at `target`, image rows parallel to the
// horizontal plane (world up is +y), square pixels, principal point at the image centre.
ProjectorCalibration projectorLookingAt(int width, int height, double verticalFovDegrees,
                                        const Vec3d& eye, const Vec3d& target);

// The demo's projector: 1920 × 1080, 30° vertical field of view, on the +z side of `target`
// (by default the middle of the procedural vase) at `distance` metres, level with it.
ProjectorCalibration makeDemoProjector(double distance, const Vec3d& target = {0, 0.075, 0});

}  // namespace vpe::scene
