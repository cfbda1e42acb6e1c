// SPDX-License-Identifier: MIT
// vpe scan CAPTURE --calibration procam.yml --out DIR [--truth DIR]
#include <chrono>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/seconds_since.h"
#include "vpe/registration/surface_mesh.h"
#include "vpe/scan/scan_accuracy.h"
#include "vpe/scan/scan_files.h"
#include "vpe/scene/projector_calibration.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct ScanArguments {
    std::string capture, calibration, calibrationUnit, out, truth;
    double minCoverage = 0.5;
    int threads = 0;
    bool json = false;
};

void runScan(const ScanArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const structured_light::ScanCapture capture(args.capture);
    // A file without the projector's size (procam-calibration's) is the scan's projector; T's
    // unit from the file, else --calibration-unit.
    scene::ProjectorCalibrationOverrides overrides;
    overrides.defaultWidth = capture.manifest().patterns.width;
    overrides.defaultHeight = capture.manifest().patterns.height;
    if (!args.calibrationUnit.empty()) {
        overrides.metresPerUnit = scene::metresPerLengthUnit(args.calibrationUnit);
    }
    scan::ProcamRig rig;
    rig.projector = scene::readProjectorCalibration(args.calibration, overrides);
    const auto camera = scene::readCameraCalibration(args.calibration);
    if (!camera) {
        throw common::InputError(args.calibration,
                                 "cam_K: missing (vpe scan needs the camera's intrinsics too: a "
                                 "calibration from vpe calibrate)");
    }
    rig.camera = *camera;
    structured_light::DecodeOptions decodeOptions;
    decodeOptions.threads = args.threads;
    const structured_light::DecodedScan decoded =
        structured_light::decodePatterns(capture, decodeOptions);
    const double decodeSeconds = common::secondsSince(start);
    const double decodedShare = decoded.lit ? double(decoded.decoded) / double(decoded.lit) : 0;
    if (decodedShare < args.minCoverage) {
        throw common::InputError(
            capture.folder(), "the scan covers too little of the object: " +
                                  std::to_string(static_cast<int>(100 * decodedShare)) +
                                  "% of the pixels the projector lights were decoded (at least " +
                                  std::to_string(static_cast<int>(100 * args.minCoverage)) +
                                  "% wanted; see the contact sheet's reasons: room light, "
                                  "interreflection, a moving object)");
    }
    const auto triangulateStart = std::chrono::steady_clock::now();
    scan::TriangulationOptions triangulation;
    triangulation.threads = args.threads;
    const scan::ProjectorSurface surface = scan::triangulateScan(decoded, rig, triangulation);
    const double triangulateSeconds = common::secondsSince(triangulateStart);

    const auto writeStart = std::chrono::steady_clock::now();
    common::AtomicFolder folder(args.out, scan::kSurfaceFile, "vpe scan");
    scan::writeSurface(surface, folder.temporaryPath() / scan::kSurfaceFile);
    scan::writePointCloud(surface, folder.temporaryPath() / scan::kPointCloudFile);
    scan::writeScanSheet(decoded, surface, folder.temporaryPath() / scan::kScanSheetFile);
    scan::writeDecoded(decoded, folder.temporaryPath() / scan::kDecodedFile);
    // The calibration goes with the scan (vpe bake --scan reads both), as this scan read it:
    // vpe's keys, metres, both sizes, whatever the file's layout; and the scan's own surface as
    // a mesh, for an installation without one.
    scene::writeProcamCalibration(rig.projector, rig.camera, std::nullopt,
                                  folder.temporaryPath() / scan::kCalibrationFile);
    const registration::SurfaceMesh surfaceMesh =
        registration::makeSurfaceMesh(surface, rig.projector);
    registration::writeSurfaceMesh(surfaceMesh, folder.temporaryPath());
    folder.commit();
    const double writeSeconds = common::secondsSince(writeStart);

    std::optional<scan::ScanAccuracy> accuracy;
    if (!args.truth.empty()) {
        accuracy = scan::compareWithTruth(decoded, surface, args.truth);
    }
    std::fprintf(stderr,
                 "%s: decoded %zu of %zu lit camera pixels (%.1f%%), measured %zu projector "
                 "pixels; decode %.2f s, triangulate %.2f s, write %.2f s\n",
                 args.out.c_str(), decoded.decoded, decoded.lit, 100 * decodedShare,
                 surface.measured, decodeSeconds, triangulateSeconds, writeSeconds);
    for (int a = 0; a < 2; ++a) {
        if (decoded.phaseEqualized[a]) {
            std::fprintf(stderr,
                         "the %s phase was distorted (its histogram %.0f%% off even: a DLP "
                         "projector and an exposure that is not a whole number of its frames?) "
                         "and was equalized\n",
                         a == 0 ? "column" : "row", 100 * decoded.phaseDistortion[a]);
        }
    }
    std::fprintf(stderr, "surface mesh: %zu triangles, %s chart%s\n",
                 surfaceMesh.mesh.triangleCount(),
                 registration::surfaceChartName(surfaceMesh.chart),
                 surfaceMesh.axis.valid
                     ? (" (axis of revolution fits the normals to " +
                        std::to_string(1000 * surfaceMesh.axis.rmsM).substr(0, 5) + " mm)")
                           .c_str()
                     : "");
    if (accuracy) {
        std::fprintf(stderr,
                     "against the truth: coverage %.2f%%, depth RMS %.3f mm (p99 %.3f), normals "
                     "median %.2f°, wrong decodes %.4f%% (%zu; beyond their precision %.4f%%), "
                     "decode RMS %.3f px, lit pixels decoded %.2f%%\n",
                     100 * accuracy->coverage, accuracy->depthRmsMm, accuracy->depthP99Mm,
                     accuracy->normalMedianDeg, 100 * accuracy->wrongDecodeShare,
                     accuracy->wrongDecodes, 100 * accuracy->wrongCodeShare, accuracy->decodeRmsPx,
                     100 * accuracy->litDecodedShare);
    }
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        json["camera"] = {decoded.width, decoded.height};
        json["projector"] = {decoded.projectorWidth, decoded.projectorHeight};
        json["lit_pixels"] = decoded.lit;
        json["decoded_pixels"] = decoded.decoded;
        json["decoded_share"] = decodedShare;
        nlohmann::json reasons;
        for (int s = 1; s < structured_light::kDecodeStatusCount; ++s) {
            reasons[structured_light::decodeStatusName(static_cast<structured_light::DecodeStatus>(
                s))] = decoded.statusCounts[static_cast<std::size_t>(s)];
        }
        json["undecoded"] = reasons;
        json["noise_sigma_at_half"] = decoded.noise.sigma(0.5);
        json["camera_gamma"] = decoded.cameraGamma;
        json["phase_distortion"] = {decoded.phaseDistortion[0], decoded.phaseDistortion[1]};
        json["phase_equalized"] = {decoded.phaseEqualized[0], decoded.phaseEqualized[1]};
        nlohmann::json placedBy = nlohmann::json::object();
        for (int s = 1; s < structured_light::kPositionSourceCount; ++s) {
            placedBy[structured_light::positionSourceName(
                static_cast<structured_light::PositionSource>(s))] =
                decoded.sourceCounts[static_cast<std::size_t>(s)];
        }
        json["placed_by"] = placedBy;
        json["measured_projector_pixels"] = surface.measured;
        json["completed_projector_pixels"] = surface.completed;
        json["surface_chart"] = registration::surfaceChartName(surfaceMesh.chart);
        json["surface_triangles"] = surfaceMesh.mesh.triangleCount();
        json["axis_rms_mm"] = 1000 * surfaceMesh.axis.rmsM;
        json["decode_seconds"] = decodeSeconds;
        json["triangulate_seconds"] = triangulateSeconds;
        json["scan_seconds"] = decodeSeconds + triangulateSeconds;
        json["write_seconds"] = writeSeconds;
        if (accuracy) {
            json["scan_coverage"] = accuracy->coverage;
            json["depth_rms_mm"] = accuracy->depthRmsMm;
            json["depth_p99_mm"] = accuracy->depthP99Mm;
            json["normal_median_deg"] = accuracy->normalMedianDeg;
            json["normal_p95_deg"] = accuracy->normalP95Deg;
            json["wrong_decode_share"] = accuracy->wrongDecodeShare;
            json["wrong_code_share"] = accuracy->wrongCodeShare;
            json["coarse_share"] = accuracy->coarseShare;
            json["wrong_decode_share_with_coarse"] = accuracy->wrongAmongAllShare;
            json["lit_decoded_share"] = accuracy->litDecodedShare;
            json["lit_seen_pixels"] = accuracy->litSeen;
            nlohmann::json bySource = nlohmann::json::object();
            for (int s = 1; s < structured_light::kPositionSourceCount; ++s) {
                const auto source = static_cast<structured_light::PositionSource>(s);
                bySource[structured_light::positionSourceName(source)] = {
                    {"pixels", accuracy->bySource[static_cast<std::size_t>(s)]},
                    {"rms_px", accuracy->rmsBySourcePx[static_cast<std::size_t>(s)]}};
            }
            json["decode_error_by_source"] = bySource;
            json["wrong_decodes"] = accuracy->wrongDecodes;
            json["wrong_decode_share_centre"] = accuracy->wrongAtCentreShare;
            json["decode_rms_px"] = accuracy->decodeRmsPx;
            json["measured_without_truth"] = accuracy->measuredWithoutTruth;
        }
        json["seconds"] = common::secondsSince(start);
        printJson(json.dump());
    }
}

}  // namespace

void addScanCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ScanArguments>();
    CLI::App* command = app.add_subcommand(
        "scan",
        "Decode a structured-light capture and triangulate the surface each projector "
        "pixel lights");
    command->add_option("capture", args->capture, "Scan folder (scan.json and its images)")
        ->required();
    command
        ->add_option("--calibration", args->calibration,
                     "Projector–camera calibration: vpe calibrate's YAML, or procam-calibration's "
                     "calibration_result.xml (the projector's size then the scan's)")
        ->required();
    addCalibrationUnitOption(command, args->calibrationUnit);
    command
        ->add_option("--out", args->out,
                     "Folder to write: surface.exr, points.ply, surface-mesh.obj, "
                     "contact-sheet.png, decoded.exr")
        ->required();
    command->add_option("--truth", args->truth,
                        "A simulation's truth folder (vpe synth-procam): report the errors");
    command
        ->add_option("--min-coverage", args->minCoverage,
                     "Refuse a scan that decodes less than this share of the lit pixels")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runScan(*args); }; });
}

}  // namespace vpe::cli
