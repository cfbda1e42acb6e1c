// SPDX-License-Identifier: MIT
// vpe synth-procam --out DIR                       a complete simulated installation
// vpe synth-procam --scene FILE --out DIR          a scan of a scene file, with its truth
// vpe synth-procam --scene FILE --show IMAGE --out IMAGE   what the camera sees of one image
// vpe synth-procam --scene FILE --check BUNDLE --out DIR   a measured bundle against the truth
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/quantile.h"
#include "vpe/image/contact_sheet.h"
#include "vpe/image/image_file.h"
#include "vpe/procam/gallery_installation.h"
#include "vpe/procam/installation_check.h"
#include "vpe/procam/radiometry_check.h"
#include "vpe/procam/simulated_capture.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/proto/srgb.h"
#include "vpe/renderer/procam/scene_file.h"
#include "vpe/scene/projector_calibration.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

namespace sim = renderer::procam;

struct SynthProcamArguments {
    std::string out, scene, show, check, checkLight, baseline;
    std::string projectorSize = "1920x1080", cameraSize = "1640x1232";
    int poses = 15;
    double cameraOffset = 0.21, exposure = 0.85, roomLight = 0.06, cameraBlack = 0;
    std::uint64_t seed = 1;
    std::string noise = "camera";
    // The sensor and the optics, for noise sweeps: 0 / "" keep the gallery's.
    double fullWell = 0, blur = -1, dlpExposure = -1;
    std::string cameraOutput = "linear10";
    bool stains = false;
    bool realisticLight = false;
    bool uniformPlaster = false;
    int capture = 0;  // which capture of the installation: fresh noise for each
    int phasePeriod = 32, phaseSteps = 8;
    int threads = 0;
    bool json = false;
};

nlohmann::json cameraJson(const proto::PinholeCamera& c) {
    return {{"width", c.width},           {"height", c.height}, {"K", c.K},
            {"distortion", c.distortion}, {"R", c.R},           {"T", c.T}};
}

// A room-frame device re-expressed in the camera's frame (the calibration's).
proto::PinholeCamera inCameraFrame(const proto::PinholeCamera& device,
                                   const proto::PinholeCamera& camera) {
    const sim::RigidPose roomToCamera{camera.R, camera.T};
    const sim::RigidPose roomToDevice{device.R, device.T};
    const sim::RigidPose cameraToDevice = roomToDevice.compose(roomToCamera.inverse());
    proto::PinholeCamera out = device;
    out.R = cameraToDevice.R;
    out.T = cameraToDevice.t;
    return out;
}

nlohmann::json poseJson(const sim::RigidPose& pose) {
    return {{"R", pose.R}, {"t", pose.t}};
}
// --full-well, --camera-output, --blur and --dlp-exposure over the gallery's camera and
// projector, on every capture (the board poses' too).
void applySensorOptions(const SynthProcamArguments& args, procam::GalleryInstallation& gallery) {
    renderer::procam::SimulatedCamera& camera = gallery.camera;
    if (args.fullWell != 0) {
        if (!(args.fullWell >= 50 && args.fullWell <= 1e6)) {
            throw common::InputError("--full-well must be in [50, 1000000] electrons");
        }
        camera.fullWellElectrons = args.fullWell;
    }
    if (args.cameraOutput == "gamma8") {  // an ISP's 8-bit output, value = signal^(1/2.2)
        camera.response = renderer::procam::CameraResponse::kGamma;
        camera.gamma = 2.2;
        camera.bits = 8;
    } else if (args.cameraOutput == "linear10") {  // raw 10-bit
        camera.response = renderer::procam::CameraResponse::kLinear;
        camera.bits = 10;
    }
    if (args.blur >= 0) {
        if (!(args.blur <= 20)) {
            throw common::InputError("--blur must be in [0, 20] projector pixels");
        }
        gallery.objectScene.projector.blurPixels = args.blur;
        for (renderer::procam::ProcamScene& scene : gallery.boardScenes) {
            scene.projector.blurPixels = args.blur;
        }
    }
    if (args.dlpExposure >= 0) {
        if (!(args.dlpExposure <= 100)) {
            throw common::InputError("--dlp-exposure must be in [0, 100] frames (0: off)");
        }
        gallery.objectScene.projector.dlp.exposureFrames = args.dlpExposure;
        for (renderer::procam::ProcamScene& scene : gallery.boardScenes) {
            scene.projector.dlp.exposureFrames = args.dlpExposure;
        }
    }
}

void runGallery(const SynthProcamArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    procam::GalleryOptions options;
    const SizeArgument projector = parseSizeArgument(args.projectorSize, "--projector-size", 8192);
    const SizeArgument camera = parseSizeArgument(args.cameraSize, "--camera-size", 8192);
    options.projectorWidth = projector.width;
    options.projectorHeight = projector.height;
    options.cameraWidth = camera.width;
    options.cameraHeight = camera.height;
    options.boardPoses = args.poses;
    options.cameraOffsetM = args.cameraOffset;
    options.exposure = args.exposure;
    options.roomLight = args.roomLight;
    options.cameraBlack = args.cameraBlack;
    if (!(args.cameraOffset > 0.02 && args.cameraOffset < 2) || !(args.exposure > 0) ||
        !(args.roomLight >= 0) || !std::isfinite(args.exposure + args.roomLight) ||
        !(args.cameraBlack >= 0 && args.cameraBlack < 0.5)) {
        throw common::InputError(
            "--camera-offset must be in (0.02, 2) m, --exposure positive, "
            "--room-light ≥ 0, --camera-black in [0, 0.5)");
    }
    options.seed = args.seed;
    options.noise = args.noise == "camera";
    options.stains = args.stains;
    options.realisticLight = args.realisticLight;
    options.uniformPlaster = args.uniformPlaster;
    procam::GalleryInstallation gallery = procam::makeGalleryInstallation(options);
    applySensorOptions(args, gallery);
    const int threads = static_cast<int>(common::resolveThreadCount(args.threads));

    common::AtomicFolder folder(args.out, "installation.toml", "vpe synth-procam");
    const std::filesystem::path root = folder.temporaryPath();
    std::filesystem::create_directories(root / "truth");
    std::filesystem::create_directories(root / "calibration" / "scenes");
    scene::writeScreenMeshObj(gallery.object, root / "object.obj");
    renderer::procam::writeSceneFile(root / "installation.toml", gallery.objectScene,
                                     gallery.camera, "object.obj");

    proto::StructuredLightParameters parameters{projector.width, projector.height, args.phasePeriod,
                                                args.phaseSteps};
    std::size_t patterns = 0;
    try {
        patterns = proto::StructuredLightSequence(parameters).patterns().size();
    } catch (const proto::StructuredLightError& error) {
        throw common::InputError(std::string("--phase-period/--phase-steps: ") + error.what());
    }
    const std::size_t flatFields =
        proto::radiometrySequence({projector.width, projector.height}).size();
    common::ProgressBar progress("synth-procam",
                                 patterns * (gallery.boardScenes.size() + 1) + flatFields);
    procam::SimulatedScanOptions scan;
    scan.phasePeriod = args.phasePeriod;
    scan.phaseSteps = args.phaseSteps;

    nlohmann::json truth;
    const proto::PinholeCamera& c = gallery.camera.camera;
    truth["camera"] = cameraJson(c);
    truth["camera"].erase("R");
    truth["camera"].erase("T");
    truth["projector"] = cameraJson(inCameraFrame(gallery.objectScene.projector.camera, c));
    const sim::RigidPose roomToCamera{c.R, c.T};
    truth["object_to_camera"] = poseJson(roomToCamera.compose(gallery.objectPose));
    truth["room_to_camera"] = poseJson(roomToCamera);
    nlohmann::json boards = nlohmann::json::array();
    for (std::size_t k = 0; k < gallery.boardScenes.size(); ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "pose%02zu", k + 1);
        progress.setPhase(std::string("calibration ") + name);
        renderer::procam::SimulatedCamera boardCamera = gallery.camera;
        boardCamera.samples = 3;  // sharper corners
        const sim::ProcamSimulator simulator(gallery.boardScenes[k], boardCamera, threads);
        scan.firstFrame = 1000 * (k + 1);
        scan.source = std::string("simulated:calibration/scenes/") + name + ".toml";
        renderer::procam::writeSceneFile(
            root / "calibration" / "scenes" / (std::string(name) + ".toml"), gallery.boardScenes[k],
            boardCamera, "");
        procam::writeSimulatedScan(simulator, root / "calibration" / name, scan, &progress);
        boards.push_back(poseJson(roomToCamera.compose(gallery.boardScenes[k].board->pose)));
    }
    const sim::CheckerBoard& board = gallery.board;
    truth["board"] = {{"squares", {board.squaresX, board.squaresY}},
                      {"square_mm", board.squareM * 1000},
                      {"poses_to_camera", boards}};

    progress.setPhase("object scan");
    const sim::ProcamSimulator simulator(gallery.objectScene, gallery.camera, threads);
    scan.firstFrame = 0;
    scan.source = "simulated:installation.toml";
    procam::writeSimulatedScan(simulator, root / "scan", scan, &progress);
    progress.setPhase("radiometry");
    procam::SimulatedRadiometryOptions flat;
    flat.source = scan.source;
    procam::writeSimulatedRadiometry(simulator, root / "scan" / proto::kRadiometryFolderName, flat,
                                     &progress);
    progress.setPhase("truth");
    procam::writeSimulationTruth(simulator, root / "truth");
    proto::writeTextFileAtomically(root / "truth" / "truth.json", truth.dump(2) + "\n");

    progress.finish();
    folder.commit();

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "wrote %s: a simulated installation — %zu calibration poses and an object scan "
                 "of %zu images each (projector %dx%d, camera %dx%d), the truth, in %.1f s\n",
                 args.out.c_str(), gallery.boardScenes.size(), patterns, projector.width,
                 projector.height, camera.width, camera.height, seconds);
    std::fprintf(stderr, "board: %dx%d squares of %.0f mm (vpe calibrate --board %dx%d:%.0fmm)\n",
                 board.squaresX, board.squaresY, board.squareM * 1000, board.squaresX,
                 board.squaresY, board.squareM * 1000);
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        json["poses"] = gallery.boardScenes.size();
        json["images_per_capture"] = patterns;
        json["board"] = std::to_string(board.squaresX) + "x" + std::to_string(board.squaresY) +
                        ":" + std::to_string(static_cast<int>(board.squareM * 1000)) + "mm";
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

// A camera view for people: the linear signal divided by `white`, sRGB-encoded.
image::SheetTile linearTile(std::string label, const renderer::RgbImage& image, double white) {
    image::SheetTile tile{std::move(label), image.width, image.height, 3, {}};
    tile.pixels.reserve(image.values.size());
    for (const float v : image.values) {
        const double x = std::clamp(double(v) / white, 0.0, 1.0);
        tile.pixels.push_back(static_cast<float>(proto::linearToSrgb(x)));
    }
    return tile;
}

// --check-light: how closely a bundle's compensation gives its target on the true installation,
// as the camera sees it (and a --baseline bundle's, e.g. today's assumed radiometry, beside it).
void runLightCheck(const SynthProcamArguments& args, const renderer::procam::SceneFile& file) {
    const auto start = std::chrono::steady_clock::now();
    procam::RadiometryCheckOptions options;
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    const proto::BundleFile bundle = proto::BundleFile::open(args.checkLight);
    const procam::RadiometryCheck check =
        procam::checkRadiometry(file.scene, file.camera, bundle.view(), options);
    std::optional<procam::RadiometryCheck> baseline;
    if (!args.baseline.empty()) {
        const proto::BundleFile other = proto::BundleFile::open(args.baseline);
        baseline = procam::checkRadiometry(file.scene, file.camera, other.view(), options);
    }
    std::vector<image::SheetTile> tiles;
    for (std::size_t i = 0; i < check.views.size(); ++i) {
        const procam::RadiometryView& view = check.views[i];
        std::vector<double> luminance;
        for (std::size_t p = 0; p < view.target.pixelCount(); ++p) {
            luminance.push_back(double(view.target.values[3 * p + 1]));
        }
        const double white = std::max(1e-9, common::quantile(luminance, 0.998));
        char label[128];
        std::snprintf(label, sizeof label, "light %.2f,%.2f,%.2f: the target", view.light.x,
                      view.light.y, view.light.z);
        tiles.push_back(linearTile(label, view.target, white));
        std::snprintf(label, sizeof label, "%s: %.2f levels RMS", args.checkLight.c_str(),
                      view.rmsLevels);
        tiles.push_back(linearTile(label, view.seen, white));
        if (baseline) {
            const procam::RadiometryView& other = baseline->views[i];
            std::snprintf(label, sizeof label, "%s: %.2f levels RMS", args.baseline.c_str(),
                          other.rmsLevels);
            // On the target's scale: the baseline's units are its own.
            tiles.push_back(linearTile(label, other.seen, white * other.scale));
        }
    }
    std::filesystem::create_directories(args.out);
    const std::filesystem::path sheet = std::filesystem::path(args.out) / "light-check.png";
    image::writeContactSheet(sheet, tiles, baseline ? 3 : 2, 360);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "%s on %s: %.2f levels RMS (worst light %.2f), clipped %.2f%%%s; pictures in %s; "
                 "%.1f s\n",
                 args.checkLight.c_str(), args.scene.c_str(), check.rmsLevels, check.worstRmsLevels,
                 100 * check.clippedShare,
                 baseline ? (", the baseline " + std::to_string(baseline->rmsLevels).substr(0, 5) +
                             " levels")
                                .c_str()
                          : "",
                 sheet.c_str(), seconds);
    if (args.json) {
        nlohmann::json json;
        json["rms_levels"] = check.rmsLevels;
        json["worst_rms_levels"] = check.worstRmsLevels;
        json["clipped_share"] = check.clippedShare;
        json["below_floor_share"] = check.belowFloorShare;
        nlohmann::json views = nlohmann::json::array();
        for (const procam::RadiometryView& view : check.views) {
            views.push_back({{"light", {view.light.x, view.light.y, view.light.z}},
                             {"rms_levels", view.rmsLevels},
                             {"scale", view.scale},
                             {"clipped_share", view.clippedShare},
                             {"below_floor_share", view.belowFloorShare},
                             {"pixels", view.pixels}});
        }
        json["views"] = views;
        if (baseline) {
            json["baseline_rms_levels"] = baseline->rmsLevels;
            json["baseline_worst_rms_levels"] = baseline->worstRmsLevels;
            json["baseline_clipped_share"] = baseline->clippedShare;
            json["difference_levels"] = procam::viewDifferenceLevels(check, *baseline);
        }
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

// --check: a bundle measured on the installation against its truth, with a contact sheet of what
// a visitor sees.
void runCheck(const SynthProcamArguments& args, const renderer::procam::SceneFile& file) {
    const auto start = std::chrono::steady_clock::now();
    proto::BundleFile bundle = proto::BundleFile::open(args.check);
    procam::InstallationCheckOptions options;
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    const procam::InstallationCheck check =
        procam::checkInstallation(file.scene, file.camera.camera, bundle.view(), options);
    std::vector<image::SheetTile> tiles;
    for (const procam::VisitorComparison& view : check.views) {
        const auto tileOf = [](const image::Rgb8Image& image, std::string label) {
            image::SheetTile tile{std::move(label), image.width, image.height, 3, {}};
            tile.pixels.reserve(image.values.size());
            for (const std::uint8_t v : image.values) {
                tile.pixels.push_back(static_cast<float>(v) / 255.0f);
            }
            return tile;
        };
        char light[96];
        std::snprintf(light, sizeof light, "light %.2f,%.2f,%.2f: measured, %.1f dB", view.light.x,
                      view.light.y, view.light.z, view.psnr);
        tiles.push_back(tileOf(view.measured, light));
        tiles.push_back(tileOf(view.truth, "the true geometry"));
        image::Rgb8Image difference = view.truth;
        for (std::size_t i = 0; i < difference.values.size(); ++i) {
            difference.values[i] = static_cast<std::uint8_t>(std::min(
                255, 8 * std::abs(int(view.measured.values[i]) - int(view.truth.values[i]))));
        }
        tiles.push_back(tileOf(difference, "difference x8"));
    }
    std::filesystem::create_directories(args.out);
    const std::filesystem::path sheet = std::filesystem::path(args.out) / "visitor-check.png";
    image::writeContactSheet(sheet, tiles, 3, 320);
    // The true camera in the object's frame, for the tracked lamp's error (vpe_lamp_direction).
    const std::filesystem::path trueCamera = std::filesystem::path(args.out) / "true-camera.yml";
    scene::writeCameraCalibration(check.trueCamera, trueCamera);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "%s against %s: visitor views %.2f dB (worst %.2f) over %zu lights; pose off by "
                 "%.3f mm and %.4f°%s; texture lands %.3f mm from its place (RMS; p95 %.3f, max "
                 "%.3f, %zu points); %s in %.1f s\n",
                 args.check.c_str(), args.scene.c_str(), check.psnrMean, check.psnrMin,
                 check.views.size(), check.poseErrorMm, check.poseErrorDeg,
                 check.turnFree ? " (the mesh's free turn set by the same rule on both)" : "",
                 check.misregistrationRmsMm, check.misregistrationP95Mm, check.misregistrationMaxMm,
                 check.misregistrationPoints, sheet.c_str(), seconds);
    if (args.json) {
        nlohmann::json json;
        json["psnr"] = check.psnrMean;
        json["psnr_min"] = check.psnrMin;
        nlohmann::json perLight = nlohmann::json::array();
        for (const procam::VisitorComparison& view : check.views) {
            perLight.push_back(
                {{"light", {view.light.x, view.light.y, view.light.z}}, {"psnr", view.psnr}});
        }
        json["views"] = perLight;
        json["pose_error_mm"] = check.poseErrorMm;
        json["pose_error_deg"] = check.poseErrorDeg;
        json["turn_free"] = check.turnFree;
        json["misregistration_mm"] = check.misregistrationRmsMm;
        json["misregistration_p95_mm"] = check.misregistrationP95Mm;
        json["misregistration_max_mm"] = check.misregistrationMaxMm;
        json["misregistration_points"] = check.misregistrationPoints;
        json["sheet"] = sheet.string();
        json["true_camera"] = trueCamera.string();
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

void runScene(const SynthProcamArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const renderer::procam::SceneFile file = renderer::procam::readSceneFile(args.scene);
    if (!args.check.empty()) {
        runCheck(args, file);
        return;
    }
    if (!args.checkLight.empty()) {
        runLightCheck(args, file);
        return;
    }
    const int threads = static_cast<int>(common::resolveThreadCount(args.threads));
    const sim::ProcamSimulator simulator(file.scene, file.camera, threads);
    if (!args.show.empty()) {
        const image::FloatImage shown = image::readImage(args.show);
        const proto::PinholeCamera& p = file.scene.projector.camera;
        if (shown.width != p.width || shown.height != p.height) {
            throw common::InputError(
                args.show, std::to_string(shown.width) + "x" + std::to_string(shown.height) +
                               ", but the scene's projector is " + std::to_string(p.width) + "x" +
                               std::to_string(p.height));
        }
        renderer::RgbImage levels(p.width, p.height);
        for (std::size_t i = 0; i < levels.pixelCount(); ++i) {
            for (std::size_t ch = 0; ch < 3; ++ch) {
                const int from = shown.channels >= 3 ? static_cast<int>(ch) : 0;
                levels.values[3 * i + ch] =
                    shown.pixels[i * static_cast<std::size_t>(shown.channels) +
                                 static_cast<std::size_t>(from)];
            }
        }
        const renderer::RgbImage radiance = simulator.radiance(levels);
        const std::filesystem::path out(args.out);
        if (out.extension() == ".exr") {
            image::writeImage(out, radiance.width, radiance.height, 3, radiance.values,
                              image::PixelFormat::kFloat);
        } else {
            const sim::CameraFrame frame = simulator.expose(radiance, 0);
            std::vector<float> values(frame.samples.size());
            for (std::size_t i = 0; i < values.size(); ++i) {
                values[i] =
                    static_cast<float>(frame.samples[i]) / static_cast<float>(frame.maxValue());
            }
            image::writeImage(
                out, frame.width, frame.height, frame.channels, values,
                frame.bits > 8 ? image::PixelFormat::kUint16 : image::PixelFormat::kUint8);
        }
        std::fprintf(stderr, "wrote %s: the camera's view of %s\n", args.out.c_str(),
                     args.show.c_str());
        return;
    }
    proto::StructuredLightParameters parameters{file.scene.projector.camera.width,
                                                file.scene.projector.camera.height,
                                                args.phasePeriod, args.phaseSteps};
    common::ProgressBar progress(
        "synth-procam",
        proto::StructuredLightSequence(parameters).patterns().size() +
            proto::radiometrySequence({parameters.width, parameters.height}).size());
    procam::SimulatedScanOptions scan;
    scan.phasePeriod = args.phasePeriod;
    scan.phaseSteps = args.phaseSteps;
    scan.source = "simulated:" + args.scene;
    // Each capture of the same installation draws fresh noise.
    scan.firstFrame = 100000 * static_cast<std::uint64_t>(args.capture);
    common::AtomicFolder folder(args.out, proto::kScanManifestName, "vpe synth-procam");
    procam::writeSimulatedScan(simulator, folder.temporaryPath(), scan, &progress);
    procam::SimulatedRadiometryOptions flat;
    flat.source = scan.source;
    flat.firstFrame = scan.firstFrame + 1000;
    const auto flatStart = std::chrono::steady_clock::now();
    procam::writeSimulatedRadiometry(
        simulator, folder.temporaryPath() / proto::kRadiometryFolderName, flat, &progress);
    const double flatSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - flatStart).count();
    procam::writeSimulationTruth(simulator, folder.temporaryPath() / "truth");
    progress.finish();
    folder.commit();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "wrote %s: a simulated scan of %s, its radiometric capture (%.1f s) and its "
                 "truth in %.1f s\n",
                 args.out.c_str(), args.scene.c_str(), flatSeconds, seconds);
    if (args.json) {
        printJson(nlohmann::json{
            {"out", args.out}, {"radiometry_capture_seconds", flatSeconds}, {"seconds", seconds}}
                      .dump());
    }
}

}  // namespace

void addSynthProcamCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<SynthProcamArguments>();
    CLI::App* command = app.add_subcommand(
        "synth-procam",
        "Simulate a projector–camera installation: calibration and scan captures with the truth");
    command
        ->add_option("--out", args->out,
                     "Folder to write (an installation, or one scan); with --show, the image")
        ->required();
    command->add_option("--scene", args->scene,
                        "A scene file (installation.toml) to simulate instead of the gallery");
    command->add_option("--show", args->show,
                        "With --scene: a projector image; writes what the camera records of it");
    command->add_option("--check", args->check,
                        "With --scene: a bundle baked from measurements of that installation; "
                        "report what a visitor sees of it against the truth (--out: pictures, "
                        "the true camera)");
    command->add_option("--check-light", args->checkLight,
                        "With --scene: a bundle for that installation; report how closely its "
                        "frames give their target on it, as its camera sees them (--out: "
                        "pictures)");
    command->add_option("--baseline", args->baseline,
                        "With --check-light: a second bundle to compare, e.g. baked with the "
                        "assumed albedo, ambient and response");
    command->add_option("--projector-size", args->projectorSize, "Projector resolution WxH")
        ->capture_default_str();
    command->add_option("--camera-size", args->cameraSize, "Camera resolution WxH")
        ->capture_default_str();
    command
        ->add_option("--poses", args->poses,
                     "Checkerboard poses for the calibration (0: none, the object only)")
        ->capture_default_str();
    command->add_option("--seed", args->seed, "Chooses the object's pose and the noise")
        ->capture_default_str();
    command
        ->add_option("--camera-offset", args->cameraOffset,
                     "The camera's distance to the projector's left (m)")
        ->capture_default_str();
    command
        ->add_option("--exposure", args->exposure,
                     "The camera's exposure (signal per unit radiance; 1 = full well)")
        ->capture_default_str();
    command
        ->add_option("--room-light", args->roomLight,
                     "The room's irradiance on the object, in the projector's units")
        ->capture_default_str();
    command->add_option("--full-well", args->fullWell,
                        "The sensor's full well (electrons; default the gallery's 10000): the "
                        "shot noise");
    addChoiceOption(command, "--camera-output", args->cameraOutput,
                    "linear10 (raw 10-bit, the default) or gamma8 (an ISP's 8-bit, γ 2.2)",
                    {"linear10", "gamma8"});
    command->add_option("--blur", args->blur,
                        "The projector's defocus, σ in projector pixels (default 0.7)");
    command->add_option("--dlp-exposure", args->dlpExposure,
                        "A DLP projector's bit-planes against the camera's exposure, in frame "
                        "periods (0.3, 1.5: intermediate levels read wrong; 0: off, the default)");
    command->add_option("--noise", args->noise, "camera (shot + read noise) or none")
        ->check(CLI::IsMember({"camera", "none"}))
        ->capture_default_str();
    command->add_flag("--stains", args->stains, "Non-uniform plaster: a greyer foot and stains");
    command->add_flag("--realistic-light", args->realisticLight,
                      "A gallery's light: plaster stained ±30 %, a projector response that is no "
                      "gamma, crosstalk between its primaries, room light at 2 % of its white");
    command->add_flag("--uniform-plaster", args->uniformPlaster,
                      "With --realistic-light: plaster of one albedo, no stains, no greyer foot");
    command
        ->add_option("--camera-black", args->cameraBlack,
                     "The camera sensor's black level (an offset in every value), share of "
                     "full scale")
        ->capture_default_str();
    command
        ->add_option("--capture", args->capture,
                     "With --scene: which capture of the installation (fresh noise for each)")
        ->capture_default_str();
    command->add_option("--phase-period", args->phasePeriod, "Projector pixels per sinusoid")
        ->capture_default_str();
    command->add_option("--phase-steps", args->phaseSteps, "Phase shifts per axis")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] {
        action = [args] {
            if ((!args->show.empty() || !args->check.empty() || !args->checkLight.empty()) &&
                args->scene.empty()) {
                throw common::InputError("--show, --check and --check-light need --scene FILE");
            }
            if (args->scene.empty()) {
                runGallery(*args);
            } else {
                runScene(*args);
            }
        };
    });
}

}  // namespace vpe::cli
