// SPDX-License-Identifier: MIT
// Board corners, local homographies and the three calibrations, through OpenCV's calib3d.
#include "vpe/calibrate/procam_calibrator.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "vpe/common/input_error.h"
#include "vpe/proto/srgb.h"

namespace vpe::calibrate {

namespace {

cv::Point2d point(const proto::Vec2d& p) {
    return {p.x, p.y};
}

// The white frame as 8 bits for the corner detector, sRGB-encoded: the dark squares of a linear
// camera's picture keep enough levels to be told from the toner's edges.
cv::Mat detectorImage(const std::vector<float>& white, int width, int height) {
    cv::Mat image(height, width, CV_8UC1);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const double v =
                std::clamp(double(white[static_cast<std::size_t>(y) * width + x]), 0.0, 1.0);
            image.at<std::uint8_t>(y, x) =
                static_cast<std::uint8_t>(std::lround(255 * proto::linearToSrgb(v)));
        }
    }
    return image;
}

double sample(const std::vector<float>& image, int width, int height, const cv::Point2d& p) {
    const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, width - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, height - 1);
    return image[static_cast<std::size_t>(y) * width + x];
}

std::vector<cv::Point3f> boardPoints(const BoardSpec& board) {
    std::vector<cv::Point3f> points;
    for (int k = 0; k < board.cornerCount(); ++k) {
        points.emplace_back(static_cast<float>(board.cornerX(k)),
                            static_cast<float>(board.cornerY(k)), 0.0f);
    }
    return points;
}

proto::PinholeCamera cameraOf(const cv::Mat& K, const cv::Mat& distortion, int width, int height) {
    proto::PinholeCamera camera;
    camera.width = width;
    camera.height = height;
    for (int i = 0; i < 9; ++i) {
        camera.K[static_cast<std::size_t>(i)] = K.at<double>(i / 3, i % 3);
    }
    for (int i = 0; i < 5; ++i) {
        camera.distortion[static_cast<std::size_t>(i)] =
            i < distortion.cols * distortion.rows ? distortion.at<double>(i) : 0.0;
    }
    return camera;
}

}  // namespace

BoardPose measureBoardPose(const structured_light::ScanCapture& capture,
                           const structured_light::DecodedScan& decoded, const BoardSpec& board,
                           const CornerOptions& options) {
    BoardPose pose;
    pose.folder = capture.folder();
    pose.cameraWidth = decoded.width;
    pose.cameraHeight = decoded.height;
    pose.projectorWidth = decoded.projectorWidth;
    pose.projectorHeight = decoded.projectorHeight;
    pose.white = decoded.white;
    const int w = decoded.width, h = decoded.height;
    std::vector<cv::Point2f> corners;
    const cv::Size pattern(board.cornersX(), board.cornersY());
    const cv::Mat image = detectorImage(decoded.white, w, h);
    // The sector-based detector (sub-pixel by itself), with its upsampled refinement when it
    // succeeds (it gives up on some poses that the plain pass finds); the classic detector with
    // cornerSubPix last.
    bool found = false;
    for (const int flags :
         {int(cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY), int(cv::CALIB_CB_EXHAUSTIVE)}) {
        found = found || cv::findChessboardCornersSB(image, pattern, corners, flags);
    }
    if (!found) {
        found = cv::findChessboardCorners(
            image, pattern, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
        if (found) {
            cv::cornerSubPix(
                image, corners, cv::Size(7, 7), cv::Size(-1, -1),
                cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
        }
    }
    if (!found || static_cast<int>(corners.size()) != board.cornerCount()) {
        // Other tools count a board by its inner corners: say which count --board takes.
        const std::string inner =
            std::to_string(board.cornersX()) + "x" + std::to_string(board.cornersY());
        const std::string squares =
            std::to_string(board.squaresX) + "x" + std::to_string(board.squaresY);
        throw common::InputError(pose.folder,
                                 "the board's " + inner +
                                     " inner corners were not found in the white frame (--board "
                                     "counts squares: " +
                                     squares + " squares have " + inner +
                                     " inner corners; whole board in view, in focus, lit?)");
    }
    // The first corner is the one whose up-left square is dark (BoardSpec: square (0, 0) is
    // dark); the detector may have started from the opposite corner (a half turn).
    const cv::Point2d p00 = corners[0];
    const cv::Point2d alongX = cv::Point2d(corners[1]) - p00;
    const cv::Point2d alongY =
        cv::Point2d(corners[static_cast<std::size_t>(board.cornersX())]) - p00;
    const double firstSquare = sample(decoded.white, w, h, p00 - 0.5 * alongX - 0.5 * alongY);
    const double secondSquare = sample(decoded.white, w, h, p00 + 0.5 * alongX - 0.5 * alongY);
    if (firstSquare > secondSquare) {
        std::reverse(corners.begin(), corners.end());
    }
    for (const cv::Point2f& c : corners) {
        pose.cameraCorners.push_back({c.x, c.y});
    }

    // Local homographies: decoded camera pixels around each corner → their projector pixels.
    std::size_t reached = 0;
    for (int j = 0; j < board.cornersY(); ++j) {
        for (int i = 0; i < board.cornersX(); ++i) {
            const std::size_t k = static_cast<std::size_t>(j * board.cornersX() + i);
            const cv::Point2d c = point(pose.cameraCorners[k]);
            // The square's size here, from the neighbouring corners.
            const std::size_t nx =
                static_cast<std::size_t>(j * board.cornersX() + (i > 0 ? i - 1 : i + 1));
            const std::size_t ny =
                static_cast<std::size_t>((j > 0 ? j - 1 : j + 1) * board.cornersX() + i);
            const double square = std::min(cv::norm(point(pose.cameraCorners[nx]) - c),
                                           cv::norm(point(pose.cameraCorners[ny]) - c));
            const int radius = std::max(
                options.minWindow, static_cast<int>(std::lround(options.windowShare * square)));
            std::vector<cv::Point2d> from, to;
            for (int y = static_cast<int>(c.y) - radius; y <= static_cast<int>(c.y) + radius; ++y) {
                for (int x = static_cast<int>(c.x) - radius; x <= static_cast<int>(c.x) + radius;
                     ++x) {
                    if (x < 0 || y < 0 || x >= w || y >= h) {
                        continue;
                    }
                    const std::size_t q = static_cast<std::size_t>(y) * w + x;
                    if (std::isnan(decoded.projectorX[q]) ||
                        !(double(decoded.precision[q]) <= options.maxSigma)) {
                        continue;
                    }
                    from.emplace_back(x, y);
                    to.emplace_back(decoded.projectorX[q], decoded.projectorY[q]);
                }
            }
            pose.projectorCorners.emplace_back();
            if (static_cast<int>(from.size()) < options.minPoints) {
                continue;
            }
            const cv::Mat H = cv::findHomography(from, to, cv::RANSAC, 1.0);
            if (H.empty()) {
                continue;
            }
            std::vector<cv::Point2d> mapped;
            cv::perspectiveTransform(from, mapped, H);
            double squares = 0;
            int inliers = 0;
            for (std::size_t n = 0; n < from.size(); ++n) {
                const double e = cv::norm(mapped[n] - to[n]);
                if (e < 1.0) {
                    squares += e * e;
                    ++inliers;
                }
            }
            if (inliers < options.minPoints || std::sqrt(squares / inliers) > options.maxResidual) {
                continue;
            }
            std::vector<cv::Point2d> corner{c}, projected;
            cv::perspectiveTransform(corner, projected, H);
            const cv::Point2d p = projected[0];
            if (p.x < -0.5 || p.y < -0.5 || p.x > pose.projectorWidth - 0.5 ||
                p.y > pose.projectorHeight - 0.5) {
                continue;
            }
            pose.projectorCorners.back() = proto::Vec2d{p.x, p.y};
            ++reached;
        }
    }
    if (2 * reached < static_cast<std::size_t>(board.cornerCount())) {
        throw common::InputError(pose.folder,
                                 "only " + std::to_string(reached) + " of the board's " +
                                     std::to_string(board.cornerCount()) +
                                     " corners reached the projector's light (hold the "
                                     "board where the projector lights it all)");
    }
    return pose;
}

ProcamCalibration calibrateProcam(const std::vector<BoardPose>& poses, const BoardSpec& board) {
    if (poses.size() < 3) {
        throw common::InputError("vpe calibrate needs at least 3 board poses, got " +
                                 std::to_string(poses.size()));
    }
    const BoardPose& first = poses.front();
    for (const BoardPose& pose : poses) {
        if (pose.cameraWidth != first.cameraWidth || pose.cameraHeight != first.cameraHeight ||
            pose.projectorWidth != first.projectorWidth ||
            pose.projectorHeight != first.projectorHeight) {
            throw common::InputError(pose.folder, "its camera or projector size differs from " +
                                                      first.folder.string() + "'s");
        }
    }
    const std::vector<cv::Point3f> all = boardPoints(board);
    std::vector<std::vector<cv::Point3f>> cameraObjects, projectorObjects, stereoObjects;
    std::vector<std::vector<cv::Point2f>> cameraImages, projectorImages, stereoCamera,
        stereoProjector;
    for (const BoardPose& pose : poses) {
        std::vector<cv::Point2f> cameraView, projectorView, sc, sp;
        std::vector<cv::Point3f> projectorObject, stereoObject;
        for (std::size_t k = 0; k < all.size(); ++k) {
            const cv::Point2f c(static_cast<float>(pose.cameraCorners[k].x),
                                static_cast<float>(pose.cameraCorners[k].y));
            cameraView.push_back(c);
            if (const auto& p = pose.projectorCorners[k]) {
                const cv::Point2f pp(static_cast<float>(p->x), static_cast<float>(p->y));
                projectorView.push_back(pp);
                projectorObject.push_back(all[k]);
                sc.push_back(c);
                sp.push_back(pp);
                stereoObject.push_back(all[k]);
            }
        }
        cameraObjects.push_back(all);
        cameraImages.push_back(cameraView);
        projectorObjects.push_back(projectorObject);
        projectorImages.push_back(projectorView);
        stereoObjects.push_back(stereoObject);
        stereoCamera.push_back(sc);
        stereoProjector.push_back(sp);
    }
    const cv::Size cameraSize(first.cameraWidth, first.cameraHeight);
    const cv::Size projectorSize(first.projectorWidth, first.projectorHeight);
    const int flags = cv::CALIB_FIX_K3;
    const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
    cv::Mat cameraK, cameraD, projectorK, projectorD, R, T, E, F, perView;
    std::vector<cv::Mat> rvecs, tvecs;
    try {
        cv::calibrateCamera(cameraObjects, cameraImages, cameraSize, cameraK, cameraD, rvecs, tvecs,
                            flags, criteria);
        cv::calibrateCamera(projectorObjects, projectorImages, projectorSize, projectorK,
                            projectorD, rvecs, tvecs, flags, criteria);
        cv::stereoCalibrate(stereoObjects, stereoCamera, stereoProjector, cameraK, cameraD,
                            projectorK, projectorD, cameraSize, R, T, E, F, perView,
                            cv::CALIB_USE_INTRINSIC_GUESS | flags, criteria);
    } catch (const cv::Exception& error) {
        throw common::InputError("the board poses do not determine a calibration (" + error.err +
                                 "): more poses, tilted more, over more of both images");
    }
    ProcamCalibration result;
    result.camera = cameraOf(cameraK, cameraD, first.cameraWidth, first.cameraHeight);
    result.projector =
        cameraOf(projectorK, projectorD, first.projectorWidth, first.projectorHeight);
    for (int i = 0; i < 9; ++i) {
        result.projector.R[static_cast<std::size_t>(i)] = R.at<double>(i / 3, i % 3);
    }
    for (int i = 0; i < 3; ++i) {
        result.projector.T[static_cast<std::size_t>(i)] = T.at<double>(i);
    }
    // Per device, over every view: the stereo's per-view RMS, weighted by the view's corners.
    double cameraSquares = 0, projectorSquares = 0, stereoSquares = 0;
    std::size_t points = 0;
    for (std::size_t v = 0; v < poses.size(); ++v) {
        const double n = static_cast<double>(stereoObjects[v].size());
        const double ec = perView.at<double>(static_cast<int>(v), 0);
        const double ep = perView.at<double>(static_cast<int>(v), 1);
        cameraSquares += n * ec * ec;
        projectorSquares += n * ep * ep;
        stereoSquares += n * (ec * ec + ep * ep);
        points += stereoObjects[v].size();
        result.poses.push_back({poses[v].folder, static_cast<int>(all.size()),
                                static_cast<int>(stereoObjects[v].size()), ec, ep});
    }
    result.cameraRms = std::sqrt(cameraSquares / static_cast<double>(points));
    result.projectorRms = std::sqrt(projectorSquares / static_cast<double>(points));
    result.stereoRms = std::sqrt(stereoSquares / static_cast<double>(2 * points));
    for (const double v : result.projector.K) {
        if (!std::isfinite(v)) {
            throw common::InputError("the board poses do not determine a calibration (not finite)");
        }
    }
    return result;
}

}  // namespace vpe::calibrate
