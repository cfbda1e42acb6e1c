// SPDX-License-Identifier: MIT
// vpe calibrate POSE... --board 10x7:25mm --out procam.yml [--truth truth.json] [--hold-out]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/calibrate/held_out_poses.h"
#include "vpe/calibrate/procam_calibrator.h"
#include "vpe/common/input_error.h"
#include "vpe/common/progress_bar.h"
#include "vpe/image/contact_sheet.h"
#include "vpe/proto/srgb.h"
#include "vpe/scene/projector_calibration.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct CalibrateArguments {
    std::vector<std::string> poses;
    std::string board, out, truth;
    int threads = 0;
    bool json = false, holdOut = false;
};

// A simulation's truth (vpe synth-procam's truth/truth.json) against the calibration.
struct TruthErrors {
    double intrinsicsPct = 0;  // the worst of fx, fy, cx, cy of both devices, relative
    double extrinsicMm = 0, extrinsicDeg = 0;
};

TruthErrors compareWithTruth(const calibrate::ProcamCalibration& c, const std::string& path) {
    std::ifstream stream(path);
    if (!stream) {
        throw common::InputError(path,
                                 "cannot open the truth (vpe synth-procam's truth/truth.json)");
    }
    nlohmann::json truth;
    try {
        stream >> truth;
    } catch (const nlohmann::json::exception& error) {
        throw common::InputError(path, std::string("not JSON: ") + error.what());
    }
    TruthErrors errors;
    try {
        for (const auto& [device, measured] :
             {std::pair{"camera", &c.camera}, std::pair{"projector", &c.projector}}) {
            const auto K = truth.at(device).at("K").get<std::vector<double>>();
            for (const int i : {0, 4, 2, 5}) {
                errors.intrinsicsPct =
                    std::max(errors.intrinsicsPct,
                             100 * std::abs(measured->K[static_cast<std::size_t>(i)] - K[i]) /
                                 std::abs(K[i]));
            }
        }
        const auto R = truth.at("projector").at("R").get<std::vector<double>>();
        const auto T = truth.at("projector").at("T").get<std::vector<double>>();
        double squares = 0;
        for (int i = 0; i < 3; ++i) {
            squares += std::pow(c.projector.T[static_cast<std::size_t>(i)] - T[i], 2);
        }
        errors.extrinsicMm = 1000 * std::sqrt(squares);
        // The angle of R_measured · R_trueᵀ.
        double trace = 0;
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < 3; ++k) {
                trace += c.projector.R[static_cast<std::size_t>(3 * i + k)] * R[3 * i + k];
            }
        }
        errors.extrinsicDeg = std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180 / kPi;
    } catch (const nlohmann::json::exception& error) {
        throw common::InputError(path, std::string("not a simulation's truth: ") + error.what());
    }
    return errors;
}

// Per pose: the camera's white frame with the corners found (green) and those that did not
// reach the projector (red).
void writePoseSheet(const std::vector<calibrate::BoardPose>& poses,
                    const std::filesystem::path& path) {
    std::vector<image::SheetTile> tiles;
    for (const calibrate::BoardPose& pose : poses) {
        image::SheetTile tile{
            pose.folder.filename().string(), pose.cameraWidth, pose.cameraHeight, 3, {}};
        tile.pixels.resize(pose.white.size() * 3);
        for (std::size_t p = 0; p < pose.white.size(); ++p) {
            const auto encoded = static_cast<float>(
                proto::linearToSrgb(std::clamp(double(pose.white[p]), 0.0, 1.0)));
            tile.pixels[3 * p] = tile.pixels[3 * p + 1] = tile.pixels[3 * p + 2] = encoded;
        }
        const int radius = std::max(2, pose.cameraWidth / 200);
        for (std::size_t k = 0; k < pose.cameraCorners.size(); ++k) {
            const bool reached = pose.projectorCorners[k].has_value();
            const int cx = static_cast<int>(std::lround(pose.cameraCorners[k].x));
            const int cy = static_cast<int>(std::lround(pose.cameraCorners[k].y));
            for (int dy = -radius; dy <= radius; ++dy) {
                for (int dx = -radius; dx <= radius; ++dx) {
                    const int x = cx + dx, y = cy + dy;
                    if (x < 0 || y < 0 || x >= pose.cameraWidth || y >= pose.cameraHeight ||
                        dx * dx + dy * dy > radius * radius) {
                        continue;
                    }
                    float* rgb =
                        &tile.pixels[3 * (static_cast<std::size_t>(y) * pose.cameraWidth + x)];
                    rgb[0] = reached ? 0.1f : 1.0f;
                    rgb[1] = reached ? 0.9f : 0.1f;
                    rgb[2] = 0.1f;
                }
            }
        }
        tiles.push_back(std::move(tile));
    }
    image::writeContactSheet(path, tiles, 4, 400);
}

void runCalibrate(const CalibrateArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const calibrate::BoardSpec board = calibrate::parseBoardSpec(args.board);
    if (args.holdOut && args.poses.size() < 4) {
        throw common::InputError(
            "--hold-out needs at least 4 board poses (each held-in "
            "calibration needs 3), got " +
            std::to_string(args.poses.size()));
    }
    std::vector<calibrate::BoardPose> poses;
    common::ProgressBar progress("calibrate", args.poses.size());
    for (const std::string& folder : args.poses) {
        progress.setPhase(std::filesystem::path(folder).filename().string());
        const structured_light::ScanCapture capture(folder);
        structured_light::DecodeOptions decode;
        decode.threads = args.threads;
        const structured_light::DecodedScan decoded =
            structured_light::decodePatterns(capture, decode);
        poses.push_back(calibrate::measureBoardPose(capture, decoded, board));
        progress.advance();
    }
    progress.setPhase("calibrating");
    const calibrate::ProcamCalibration calibration = calibrate::calibrateProcam(poses, board);
    std::optional<calibrate::HeldOutPoses> heldOut;
    if (args.holdOut) {
        progress.setPhase("holding out");
        heldOut = calibrate::evaluateHeldOutPoses(poses, board);
    }
    progress.finish();
    scene::writeProcamCalibration(calibration.projector, calibration.camera, calibration.stereoRms,
                                  args.out);
    const std::filesystem::path out(args.out);
    const std::filesystem::path sheet = out.parent_path() / (out.stem().string() + "-poses.png");
    writePoseSheet(poses, sheet);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::fprintf(stderr,
                 "%s: %zu poses; reprojection RMS camera %.3f px, projector %.3f px (stereo "
                 "%.3f); baseline %.1f mm; in %.1f s (corners: %s)\n",
                 args.out.c_str(), poses.size(), calibration.cameraRms, calibration.projectorRms,
                 calibration.stereoRms,
                 1000 * std::hypot(calibration.projector.T[0], calibration.projector.T[1],
                                   calibration.projector.T[2]),
                 seconds, sheet.c_str());
    if (heldOut) {
        std::string perPose;
        for (const calibrate::HeldOutPose& pose : heldOut->poses) {
            char text[32];
            std::snprintf(text, sizeof text, "%s%.2f", perPose.empty() ? "" : ", ", pose.rms);
            perPose += text;
        }
        std::fprintf(stderr,
                     "held-out poses: each predicted in the projector by the others' "
                     "calibration, RMS %.3f px, median %.3f px (per pose %s)\n",
                     heldOut->rms, heldOut->median, perPose.c_str());
    }
    std::optional<TruthErrors> errors;
    if (!args.truth.empty()) {
        errors = compareWithTruth(calibration, args.truth);
        std::fprintf(stderr,
                     "against the truth: intrinsics within %.3f%%, extrinsic %.3f mm and %.4f°\n",
                     errors->intrinsicsPct, errors->extrinsicMm, errors->extrinsicDeg);
    }
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        json["poses"] = poses.size();
        json["camera_rms_px"] = calibration.cameraRms;
        json["projector_rms_px"] = calibration.projectorRms;
        json["stereo_rms_px"] = calibration.stereoRms;
        json["calibration_rms_px"] = std::max(calibration.cameraRms, calibration.projectorRms);
        json["camera_K"] = calibration.camera.K;
        json["camera_distortion"] = calibration.camera.distortion;
        json["projector_K"] = calibration.projector.K;
        json["projector_distortion"] = calibration.projector.distortion;
        json["R"] = calibration.projector.R;
        json["T"] = calibration.projector.T;
        nlohmann::json perPose = nlohmann::json::array();
        for (const calibrate::PoseError& pose : calibration.poses) {
            perPose.push_back({{"folder", pose.folder.string()},
                               {"camera_corners", pose.cameraCorners},
                               {"projector_corners", pose.projectorCorners},
                               {"camera_rms_px", pose.cameraRms},
                               {"projector_rms_px", pose.projectorRms}});
        }
        json["per_pose"] = perPose;
        if (heldOut) {
            json["heldout_projector_rms_px"] = heldOut->rms;
            json["heldout_projector_median_px"] = heldOut->median;
            nlohmann::json heldOutPerPose = nlohmann::json::array();
            for (const calibrate::HeldOutPose& pose : heldOut->poses) {
                heldOutPerPose.push_back({{"folder", pose.folder.string()},
                                          {"rms_px", pose.rms},
                                          {"corners", pose.corners}});
            }
            json["heldout_per_pose"] = heldOutPerPose;
        }
        if (errors) {
            json["intrinsics_error_pct"] = errors->intrinsicsPct;
            json["extrinsic_mm"] = errors->extrinsicMm;
            json["extrinsic_deg"] = errors->extrinsicDeg;
        }
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addCalibrateCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<CalibrateArguments>();
    CLI::App* command = app.add_subcommand(
        "calibrate",
        "Calibrate a projector and a camera from checkerboard poses under structured light");
    command
        ->add_option("poses", args->poses,
                     "Scan folders, one per board pose (vpe-player --scan; at least 3)")
        ->required();
    command
        ->add_option("--board", args->board,
                     "The printed board: COLSxROWS:SIZE in squares, e.g. 10x7:25mm")
        ->required();
    command
        ->add_option("--out", args->out,
                     "Calibration to write (.yml: procam keys + cam_K, cam_kc; what vpe scan "
                     "and vpe bake --projector read)")
        ->required();
    command->add_option("--truth", args->truth,
                        "A simulation's truth.json (vpe synth-procam): report the errors");
    command->add_flag("--hold-out", args->holdOut,
                      "Also leave each pose out in turn: calibrate on the others and predict "
                      "its corners in the projector (N more calibrations; at least 4 poses)");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runCalibrate(*args); }; });
}

}  // namespace vpe::cli
