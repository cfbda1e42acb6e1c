// SPDX-License-Identifier: MIT
// Held-out poses through calibrateProcam, cv::solvePnP and cv::projectPoints.
#include "vpe/calibrate/held_out_poses.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <opencv2/calib3d.hpp>

#include "vpe/common/input_error.h"

namespace vpe::calibrate {

namespace {

cv::Mat intrinsicsOf(const proto::PinholeCamera& camera) {
    return cv::Mat(3, 3, CV_64F, const_cast<double*>(camera.K.data())).clone();
}

cv::Mat distortionOf(const proto::PinholeCamera& camera) {
    return cv::Mat(1, 5, CV_64F, const_cast<double*>(camera.distortion.data())).clone();
}

// The held-in calibration's prediction of the left-out pose's projector corners, and their
// distances to the decoded ones (pixels).
std::vector<double> predictionErrors(const ProcamCalibration& heldIn, const BoardPose& pose,
                                     const BoardSpec& board) {
    std::vector<cv::Point3d> board3d;
    std::vector<cv::Point2d> camera;
    for (int k = 0; k < board.cornerCount(); ++k) {
        board3d.emplace_back(board.cornerX(k), board.cornerY(k), 0.0);
        const proto::Vec2d& c = pose.cameraCorners[static_cast<std::size_t>(k)];
        camera.emplace_back(c.x, c.y);
    }
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(board3d, camera, intrinsicsOf(heldIn.camera), distortionOf(heldIn.camera),
                      rvec, tvec)) {
        throw common::InputError(pose.folder,
                                 "its board's pose could not be found from its camera corners");
    }
    // Board → camera (rvec, tvec), then camera → projector (R, T).
    cv::Mat boardR;
    cv::Rodrigues(rvec, boardR);
    const cv::Mat R = cv::Mat(3, 3, CV_64F, const_cast<double*>(heldIn.projector.R.data()));
    const cv::Mat T = cv::Mat(3, 1, CV_64F, const_cast<double*>(heldIn.projector.T.data()));
    cv::Mat projectorRvec;
    cv::Rodrigues(R * boardR, projectorRvec);
    const cv::Mat projectorTvec = R * tvec + T;
    std::vector<cv::Point3d> reached;
    std::vector<cv::Point2d> decoded;
    for (int k = 0; k < board.cornerCount(); ++k) {
        if (const auto& p = pose.projectorCorners[static_cast<std::size_t>(k)]) {
            reached.push_back(board3d[static_cast<std::size_t>(k)]);
            decoded.emplace_back(p->x, p->y);
        }
    }
    std::vector<cv::Point2d> predicted;
    cv::projectPoints(reached, projectorRvec, projectorTvec, intrinsicsOf(heldIn.projector),
                      distortionOf(heldIn.projector), predicted);
    std::vector<double> errors;
    for (std::size_t n = 0; n < decoded.size(); ++n) {
        errors.push_back(cv::norm(predicted[n] - decoded[n]));
    }
    return errors;
}

double rmsOf(const std::vector<double>& errors) {
    double squares = 0;
    for (const double e : errors) {
        squares += e * e;
    }
    return errors.empty() ? 0.0 : std::sqrt(squares / static_cast<double>(errors.size()));
}

}  // namespace

HeldOutPoses evaluateHeldOutPoses(const std::vector<BoardPose>& poses, const BoardSpec& board) {
    if (poses.size() < 4) {
        throw common::InputError(
            "holding poses out needs at least 4 board poses (each held-in calibration needs 3), "
            "got " +
            std::to_string(poses.size()));
    }
    HeldOutPoses result;
    std::vector<double> all;
    for (std::size_t i = 0; i < poses.size(); ++i) {
        std::vector<BoardPose> heldIn;
        for (std::size_t j = 0; j < poses.size(); ++j) {
            if (j != i) {
                heldIn.push_back(poses[j]);
            }
        }
        std::optional<ProcamCalibration> calibration;
        try {
            calibration = calibrateProcam(heldIn, board);
        } catch (const common::InputError& error) {
            throw common::InputError(poses[i].folder,
                                     std::string("held out, the other poses: ") + error.what());
        }
        const std::vector<double> errors = predictionErrors(*calibration, poses[i], board);
        result.poses.push_back({poses[i].folder, static_cast<int>(errors.size()), rmsOf(errors)});
        all.insert(all.end(), errors.begin(), errors.end());
    }
    result.rms = rmsOf(all);
    std::sort(all.begin(), all.end());
    const std::size_t n = all.size();
    result.median = n == 0 ? 0.0 : n % 2 == 1 ? all[n / 2] : (all[n / 2 - 1] + all[n / 2]) / 2;
    return result;
}

}  // namespace vpe::calibrate
