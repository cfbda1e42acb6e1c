// SPDX-License-Identifier: MIT
// vpe radiometry CAPTURE --scan SCAN --out DIR: the projector's light on the object, measured.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/progress_bar.h"
#include "vpe/radiometry/projector_radiometry.h"
#include "vpe/scan/scan_files.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/scene_settings.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct RadiometryArguments {
    std::string capture, scan, out, cameraBlack;
    int threads = 0;
    bool json = false;
};

void runRadiometry(const RadiometryArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    // A scan folder holding the capture in radiometry/, or the capture's own folder.
    std::filesystem::path capture = args.capture;
    if (std::filesystem::exists(capture / proto::kRadiometryFolderName /
                                proto::kRadiometryManifestName)) {
        capture /= proto::kRadiometryFolderName;
    }
    const std::filesystem::path calibration =
        std::filesystem::path(args.scan) / scan::kCalibrationFile;
    const proto::PinholeCamera projector = scene::readProjectorCalibration(calibration);
    const auto camera = scene::readCameraCalibration(calibration);
    if (!camera) {
        throw common::InputError(calibration,
                                 "cam_K: missing (the scan's calibration names the camera)");
    }
    const scan::ProjectorSurface surface =
        scan::readSurface(std::filesystem::path(args.scan) / scan::kSurfaceFile);
    const proto::RadiometryManifest manifest = proto::readRadiometryManifest(capture);
    radiometry::RadiometryOptions options;
    options.threads = args.threads;
    if (!args.cameraBlack.empty()) {
        options.cameraBlack = scene::parseBlackLevel(args.cameraBlack, "--camera-black");
    }
    common::ProgressBar progress("radiometry", manifest.images.size());
    const radiometry::ProjectorRadiometry measured =
        radiometry::measureRadiometry(capture, surface, *camera, projector, options, &progress);
    progress.finish();

    common::AtomicFolder folder(args.out, radiometry::kMeasuredFile, "vpe radiometry");
    radiometry::writeRadiometry(measured, folder.temporaryPath());
    radiometry::writeRadiometrySheet(measured, surface, projector,
                                     folder.temporaryPath() / radiometry::kRadiometrySheetFile);
    folder.commit();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const auto& x = measured.mixing;
    std::fprintf(
        stderr,
        "%s: %zu projector pixels measured; crosstalk (camera channel from primary) "
        "R %.3f %.3f %.3f | G %.3f %.3f %.3f | B %.3f %.3f %.3f, one for the whole "
        "projector%s; %.1f s\n",
        args.out.c_str(), measured.measured, x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8],
        [&] {
            for (std::size_t i = 0; i < 9; ++i) {
                if (measured.mixingSpread[i] > 2 * measured.mixingNoise[i] + 0.005) {
                    return " (it varies over the object more than noise explains: a "
                           "per-pixel matrix would fit better)";
                }
            }
            return "";
        }(),
        seconds);
    std::fprintf(stderr, "%s: %s\n", args.out.c_str(),
                 radiometry::describeFloorSplit(measured.floorSplit).c_str());
    if (args.json) {
        // What measured.json holds (the split with its errors: null where the object cannot tell
        // it), and the times.
        std::ifstream file(std::filesystem::path(args.out) / radiometry::kMeasuredFile);
        nlohmann::json json = nlohmann::json::parse(file);
        json["out"] = args.out;
        json["fit_seconds"] = measured.fitSeconds;
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addRadiometryCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<RadiometryArguments>();
    CLI::App* command = app.add_subcommand(
        "radiometry",
        "Measure the projector's light on the object from flat fields: per projector pixel the "
        "irradiance factor and the floor, the crosstalk and the response");
    command
        ->add_option("capture", args->capture,
                     "The radiometric capture (radiometry.json and its images), or the scan "
                     "folder holding it in radiometry/")
        ->required();
    command
        ->add_option("--scan", args->scan, "vpe scan's --out: its surface.exr and calibration.yml")
        ->required();
    command
        ->add_option("--out", args->out,
                     "Folder to write: irradiance.exr, floor.exr, response.csv, measured.json, "
                     "contact-sheet.png")
        ->required();
    command->add_option(
        "--camera-black", args->cameraBlack,
        "The camera's black level, one value or r,g,b, share of its linear range (the mean of a "
        "raw frame with the lens capped): splits the floor on plaster of one albedo");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runRadiometry(*args); }; });
}

}  // namespace vpe::cli
