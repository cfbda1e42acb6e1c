// SPDX-License-Identifier: MIT
// Projector–camera calibration after Moreno and Taubin ("Simple, Accurate, and Robust
// Projector-Camera Calibration", 3DIMPVT 2012): the board's corners are found in the camera's
// white frame; around each corner the decoded structured light gives a local homography from
// camera to projector pixels, which carries the corner into the projector's image; then the
// camera and the projector are each calibrated as cameras, and the pair as a stereo rig
// (OpenCV's calib3d).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/calibrate/board_spec.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/structured_light/pattern_decoder.h"

namespace vpe::calibrate {

struct CornerOptions {
    // The local homography's window: this share of a square's size in the camera image, each
    // side of the corner, at least minWindow pixels.
    double windowShare = 0.4;
    int minWindow = 5;
    // Decoded pixels a window needs, and how well they must fit their homography (RMS,
    // projector pixels).
    int minPoints = 24;
    double maxResidual = 0.5;
    // Decoded pixels placed coarser than this (σ, projector pixels: DecodedScan::precision) stay
    // out of the window: a wide Gray bin where the phase could not help. A Gray code down to
    // single pixels (σ = 1/√12) stays in.
    double maxSigma = 0.5;
};

// One board pose: where its inner corners are in the camera (all of them, row by row from the
// board's first corner) and in the projector (those the structured light reached).
struct BoardPose {
    std::filesystem::path folder;
    int cameraWidth = 0, cameraHeight = 0, projectorWidth = 0, projectorHeight = 0;
    std::vector<proto::Vec2d> cameraCorners;
    std::vector<std::optional<proto::Vec2d>> projectorCorners;
    std::vector<float> white;  // the camera's white frame, for pictures
};

// Finds the board and carries its corners into the projector. Throws InputError naming the
// pose's folder when the board is not found, or when fewer than half its corners reach the
// projector.
BoardPose measureBoardPose(const structured_light::ScanCapture& capture,
                           const structured_light::DecodedScan& decoded, const BoardSpec& board,
                           const CornerOptions& options = {});

struct PoseError {
    std::filesystem::path folder;
    int cameraCorners = 0, projectorCorners = 0;
    double cameraRms = 0, projectorRms = 0;  // pixels, after the stereo calibration
};

struct ProcamCalibration {
    proto::PinholeCamera camera;     // at the origin: the calibration's frame is the camera's
    proto::PinholeCamera projector;  // camera frame → projector (R, T, metres)
    // Reprojection RMS (pixels) of each device over every corner it saw, with the joint
    // (stereo) parameters; and the stereo calibration's own, over both.
    double cameraRms = 0, projectorRms = 0, stereoRms = 0;
    std::vector<PoseError> poses;
};

// Needs at least 3 poses, each with corners in both devices. Lens models: k1, k2, p1, p2 (k3
// fixed at 0, as procam-calibration does: k3 overfits boards that do not reach the corners).
// Throws InputError when the poses cannot determine a calibration.
ProcamCalibration calibrateProcam(const std::vector<BoardPose>& poses, const BoardSpec& board);

}  // namespace vpe::calibrate
