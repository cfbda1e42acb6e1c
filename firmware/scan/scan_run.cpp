// SPDX-License-Identifier: MIT
// runScan: the camera, the display, the sequence through the capture loop, the radiometric
// capture after it, and the folder.
#include "vpe/firmware/scan/scan_run.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "vpe/firmware/loop/event_loop.h"
#include "vpe/firmware/player/frame_report.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/player/player_log.h"
#include "vpe/firmware/scan/capture_loop.h"
#include "vpe/firmware/scan/libcamera_scan_camera.h"
#include "vpe/firmware/scan/pattern_projector.h"
#include "vpe/firmware/scan/radiometric_capture.h"
#include "vpe/firmware/scan/scan_folder.h"
#include "vpe/firmware/scan/simulated_scan_camera.h"
#include "vpe/firmware/tracking/camera_config.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/proto/structured_light.h"

#include "scan_time.h"

namespace vpe::firmware {

namespace gles = renderer::gles;

namespace {

using scan_time::msBetween;
using scan_time::numberText;

// The still stream's buffers: one being filled, one completed, one with us.
constexpr unsigned kStillBuffers = 3;
// The longest frame the camera may take when the exposure is short (µs): a frame rate that
// need not be high, with room for exposures up to it.
constexpr std::int64_t kLongestFrameUs = 100'000;
// A projector's time to lock onto the mode the display just set (the board may say otherwise).
constexpr double kKmsSettleMs = 1000;

std::string sizeText(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

// The camera the board asks for: the simulation, or the lamp's camera ([camera] id, enabled)
// on a projector (kms). Refused before anything is opened.
std::optional<CameraConfig> scanCameraConfig(const BoardConfig& board, const ScanConfig& scan) {
    const bool headless = board.display.backend == DisplayBackend::kHeadless;
    if (scan.simulate) {
        if (!headless) {
            throw PlayerInputError(board.source +
                                   ":scan.simulate: the simulated camera needs the headless "
                                   "display (display.backend is \"kms\")");
        }
        return std::nullopt;
    }
    const toml::table* section = board.section("camera");
    if (section == nullptr) {
        throw PlayerInputError(board.source +
                               ":camera: missing; the scan photographs with the lamp's camera "
                               "([camera] enabled and id), or set scan.simulate");
    }
    CameraConfig camera = parseCameraConfig(*section, board.source);
    if (!camera.enabled) {
        throw PlayerInputError(board.source +
                               ":camera.enabled: false; the scan photographs with the lamp's "
                               "camera: enable it (or set scan.simulate)");
    }
    if (headless) {
        throw PlayerInputError(board.source +
                               ":display.backend: \"headless\" shows the patterns to no "
                               "projector; a scan with a camera needs \"kms\" (or scan.simulate)");
    }
    return camera;
}

CameraStreamSettings stillStreamOf(const CameraConfig& camera, const ScanConfig& scan) {
    CameraStreamSettings settings;
    settings.id = camera.id;
    settings.width = scan.cameraWidth;
    settings.height = scan.cameraHeight;
    settings.role = CameraStreamRole::kStillCapture;
    settings.exposureUs = scan.exposureUs;
    settings.analogueGain = scan.analogueGain;
    settings.fixedWhiteBalance = true;
    settings.colourGains = scan.colourGains;
    settings.frameDurationUs = std::array<std::int64_t, 2>{
        scan.exposureUs, std::max<std::int64_t>(scan.exposureUs, kLongestFrameUs)};
    settings.minBuffers = kStillBuffers;
    // The radiometric capture photographs in colour: a stream with chroma (the scan reads its Y).
    settings.colour = scan.radiometry;
    return settings;
}

// The projector's size: the display's mode (KMS), else --size, the board's render size, or the
// simulated projector's. A simulated projector must be the display.
std::array<int, 2> projectorSizeOf(const gles::GraphicsPlatform& platform,
                                   const PlayerOptions& options, const BoardConfig& board,
                                   const SimulatedScanCamera* simulated,
                                   const std::filesystem::path& sceneFile) {
    std::array<int, 2> size{0, 0};
    std::string from;
    if (const std::optional<std::array<int, 2>> fixed = platform.fixedTargetSize()) {
        size = *fixed;
        if (options.width && (*options.width != size[0] || *options.height != size[1])) {
            throw PlayerInputError("--size: " + sizeText(*options.width, *options.height) +
                                   " differs from the display's mode " +
                                   sizeText(size[0], size[1]));
        }
        return size;
    }
    if (options.width) {
        size = {*options.width, *options.height};
        from = "--size";
    } else if (board.render.width) {
        size = {*board.render.width, *board.render.height};
        from = board.source + ":render.size";
    } else if (simulated != nullptr) {
        return {simulated->projectorWidth(), simulated->projectorHeight()};
    } else {
        throw PlayerInputError("--size: missing (the headless display has no projector size)");
    }
    if (simulated != nullptr &&
        (size[0] != simulated->projectorWidth() || size[1] != simulated->projectorHeight())) {
        throw PlayerInputError(from + ": " + sizeText(size[0], size[1]) +
                               " differs from the simulated projector " +
                               sizeText(simulated->projectorWidth(), simulated->projectorHeight()) +
                               " (" + sceneFile.string() + ")");
    }
    return size;
}

const char* responseName(proto::CameraResponseKind response) {
    return response == proto::CameraResponseKind::kLinear ? "linear" : "unknown";
}

nlohmann::ordered_json rejectedJsonOf(
    const std::array<std::uint64_t, kFrameProblemCount>& rejected) {
    nlohmann::ordered_json json = nlohmann::ordered_json::object();
    for (int p = 1; p < kFrameProblemCount; ++p) {
        json[frameProblemName(static_cast<FrameProblem>(p))] =
            rejected[static_cast<std::size_t>(p)];
    }
    return json;
}

}  // namespace

std::unique_ptr<ScanCamera> openScanCamera(const BoardConfig& board) {
    if (!board.scan) {
        throw PlayerInputError(board.source +
                               ":scan: missing (a [scan] section: the projector's latency, the "
                               "camera's exposure and size; boards/README.md)");
    }
    const ScanConfig& scan = *board.scan;
    const std::optional<CameraConfig> cameraConfig = scanCameraConfig(board, scan);
    if (scan.simulate) {
        return std::make_unique<SimulatedScanCamera>(*scan.simulate, scan.simulatedLatencyMs);
    }
    try {
        return std::make_unique<LibcameraScanCamera>(stillStreamOf(*cameraConfig, scan));
    } catch (const CameraUnavailable& error) {
        throw PlayerInputError(error.what());
    }
}

std::array<int, 2> scanProjectorSize(const gles::GraphicsPlatform& platform,
                                     const PlayerOptions& options, const BoardConfig& board,
                                     const ScanCamera& camera) {
    const auto* simulated = dynamic_cast<const SimulatedScanCamera*>(&camera);
    return projectorSizeOf(platform, options, board, simulated,
                           board.scan ? board.scan->simulate.value_or("") : "");
}

ScanReport runCapture(const BoardConfig& board, CaptureKind kind, ScanFolder& folder,
                      CaptureStage& stage, const CaptureObserver& observer) {
    if (!board.scan) {
        throw PlayerInputError(board.source + ":scan: missing");
    }
    const ScanConfig& scan = *board.scan;
    ScanCamera& camera = stage.camera;
    const int width = stage.target.width(), height = stage.target.height();

    ScanReport report;
    report.kind = kind;
    report.out = folder.out();
    report.latencyMs = scan.latencyMs;
    report.simulated = scan.simulate.has_value();
    report.simulatedLatencyMs = scan.simulatedLatencyMs;
    report.camera = camera.info();
    report.platform = stage.platform;
    report.projectorWidth = width;
    report.projectorHeight = height;
    report.phasePeriod = scan.phasePeriod;
    report.phaseSteps = scan.phaseSteps;

    proto::StructuredLightParameters parameters;
    parameters.width = width;
    parameters.height = height;
    parameters.phasePeriod = scan.phasePeriod;
    parameters.phaseSteps = scan.phaseSteps;
    std::optional<proto::StructuredLightSequence> sequence;
    try {
        sequence.emplace(parameters);
    } catch (const proto::StructuredLightError& error) {
        throw PlayerInputError(board.source + ":scan.phase_period: " + error.what());
    }
    std::optional<PatternProjector> projector;
    try {
        projector.emplace(stage.target);
    } catch (const gles::GraphicsError& error) {
        throw PlayerInputError(error.what());
    }

    // Whether the radiometric capture runs, and in colour how; said before anything is shown.
    ColourCapture colour;
    bool radiometry = kind == CaptureKind::kRadiometry || scan.radiometry;
    if (!radiometry) {
        report.radiometry.skipped = board.source + ":scan.radiometry is false";
    } else if (colour = camera.colourCapture(); !colour.available()) {
        report.radiometry.skipped = colour.unavailable;
        if (kind == CaptureKind::kRadiometry) {
            throw PlayerInputError("radiometry: " + colour.unavailable);
        }
        playerLog("scan: no radiometric capture: " + colour.unavailable);
        radiometry = false;
    }
    RadiometrySettings settings;
    settings.projectorWidth = width;
    settings.projectorHeight = height;
    settings.levels = scan.radiometryLevels;
    settings.check = {scan.minContrast, scan.minLitFraction, scan.tolerance};
    settings.scanMaxValue = (1 << report.camera.bits) - 1;
    std::size_t fields = 0;
    if (radiometry) {
        proto::RadiometryParameters fieldParameters;
        fieldParameters.width = width;
        fieldParameters.height = height;
        fieldParameters.levels = scan.radiometryLevels;
        fieldParameters.cameraResponse = colour.response;
        fields = proto::radiometrySequence(fieldParameters).size();
    }

    const std::vector<proto::PatternSpec>& patterns = sequence->patterns();
    report.patterns = kind == CaptureKind::kScan ? patterns.size() : 0;
    CaptureProgress progress;
    progress.total = report.patterns + fields;
    const auto accepted = [&observer, &progress](const std::string& step) {
        progress.step = step;
        ++progress.done;
        if (observer.progress) {
            observer.progress(progress);
        }
    };

    const std::int64_t scanBeginNs = scanClockNs();
    CaptureLoop loop(*projector, camera, stage.interrupted, width, height,
                     {scan.latencyMs, scan.retries, scan.retryWaitMs});
    // Black first, for as long as the projector needs to take the new mode: the first pattern's
    // latency is then the projector's usual one.
    loop.showBlack(
        scan.settleMs.value_or(board.display.backend == DisplayBackend::kKms ? kKmsSettleMs : 0.0));
    ScanFrameCheck check(*sequence, {scan.minContrast, scan.minLitFraction, scan.tolerance});
    CoverageMap coverage(scan.minContrast);
    if (kind == CaptureKind::kScan) {
        proto::ScanManifest manifest;
        manifest.patterns = parameters;
        manifest.camera.width = report.camera.width;
        manifest.camera.height = report.camera.height;
        manifest.camera.bits = report.camera.bits;
        manifest.camera.exposureUs = report.camera.exposureUs;
        manifest.camera.analogueGain = report.camera.analogueGain;
        manifest.camera.source = report.camera.source;
        manifest.createdBy = "vpe-player";
        manifest.images.resize(patterns.size());
        std::vector<Shot> shots;
        for (const proto::PatternSpec& pattern : patterns) {
            shots.push_back({pattern.name(), 1, CaptureRequest{}});
        }
        // What the coverage map needs until its partner arrives: white until black, a Gray
        // pattern until its inverse (groups are accepted in order).
        CameraImage held;
        const CaptureTally tally = loop.run(
            shots, check,
            [&sequence, &patterns](std::size_t index, std::span<std::uint8_t> codes) {
                sequence->render(patterns[index], codes);
            },
            [&](std::size_t index, const CameraImage& image, int attempts) {
                proto::ScanImage& entry = manifest.images[index];
                entry.file = proto::scanImageName(index, patterns[index]);
                entry.pattern = patterns[index].name();
                entry.attempts = attempts;
                proto::writePnmAtomically(folder.temporary() / entry.file, image.width,
                                          image.height, 1, image.maxValue, image.samples);
                const proto::PatternSpec& pattern = patterns[index];
                if (pattern.kind == proto::PatternKind::kWhite) {
                    held = image;
                    if (observer.cameraView) {
                        observer.cameraView(image);
                    }
                } else if (pattern.kind == proto::PatternKind::kBlack && !held.samples.empty()) {
                    coverage.setLit(held, image);
                } else if (pattern.kind == proto::PatternKind::kGray && !pattern.inverted) {
                    held = image;
                } else if (pattern.kind == proto::PatternKind::kGray && pattern.inverted) {
                    coverage.addGrayPair(held, image, check.noiseSigma());
                }
                accepted(pattern.name());
            });
        report.captures = tally.captures;
        report.retried = tally.retried;
        report.rejected = tally.rejected;
        report.captureMs = tally.captureMs;
        // How long the captures waited after their patterns: the board's latency, or the longer
        // wait the retries settled on (the longest any accepted capture used).
        manifest.projectorLatencyMs = loop.waitMs();
        proto::writeScanManifest(folder.temporary(), manifest);
        settings.scanNoiseSigma = check.noiseSigma();
    }

    // The radiometric capture, in the same session: the camera and the projector where the scan
    // left them.
    if (radiometry) {
        if (!colour.note.empty()) {
            playerLog("scan: radiometry: " + colour.note);
        }
        CameraImage white, black;
        RadiometryObserver fieldsObserver;
        fieldsObserver.accepted = [&](const proto::FlatField& field, const CameraImage& image) {
            if (kind == CaptureKind::kRadiometry && field.kind == proto::FlatFieldKind::kWhite) {
                white = image;
                if (observer.cameraView) {
                    observer.cameraView(image);
                }
            } else if (kind == CaptureKind::kRadiometry &&
                       field.kind == proto::FlatFieldKind::kBlack) {
                black = image;
            }
            if (!white.samples.empty() && !black.samples.empty() && !coverage.known()) {
                coverage.setLit(white, black);
            }
            accepted("radiometry: " + field.name());
        };
        report.radiometry = captureRadiometry(
            loop, camera, colour, settings,
            kind == CaptureKind::kScan ? folder.temporary() / proto::kRadiometryFolderName
                                       : folder.temporary(),
            fieldsObserver);
    }
    if (observer.coverage && coverage.known()) {
        observer.coverage(coverage);
    }
    folder.commit();

    const std::int64_t doneNs = scanClockNs();
    report.waitMs = loop.waitMs();
    report.litFraction = kind == CaptureKind::kScan ? check.litFraction() : coverage.litFraction();
    report.noiseSigma = check.noiseSigma();
    report.scanSeconds = msBetween(scanBeginNs, doneNs) / 1000.0;
    if (report.waitMs > scan.latencyMs) {
        playerLog("scan: the projector needed " + numberText(report.waitMs) +
                  " ms after a pattern (" + board.source + ":scan.latency_ms is " +
                  numberText(scan.latencyMs) + "): raise it");
    }
    return report;
}

ScanReport runScan(const PlayerOptions& options, const BoardConfig& board,
                   std::int64_t processStartNs) {
    // Blocked before any thread starts (libcamera's, the GL driver's), so none of them takes a
    // SIGINT that should stop the scan cleanly.
    SignalWatch signals;
    if (!board.scan) {
        throw PlayerInputError(board.source +
                               ":scan: missing (a [scan] section: the projector's latency, the "
                               "camera's exposure and size; boards/README.md)");
    }
    ScanFolder folder(*options.scan);

    // The camera before the display: no camera, no modeset (and no flash on the projector).
    const std::int64_t cameraBeginNs = scanClockNs();
    const std::unique_ptr<ScanCamera> camera = openScanCamera(board);
    const double cameraSetupMs = msBetween(cameraBeginNs, scanClockNs());

    const std::int64_t displayBeginNs = scanClockNs();
    const std::unique_ptr<gles::GraphicsPlatform> platform = createDisplayPlatform(board);
    const std::array<int, 2> size = scanProjectorSize(*platform, options, board, *camera);
    std::unique_ptr<gles::RenderTarget> target;
    try {
        target = platform->createRenderTarget(size[0], size[1]);
    } catch (const gles::GraphicsError& error) {
        throw PlayerInputError(error.what());
    }
    const double displaySetupMs = msBetween(displayBeginNs, scanClockNs());

    CaptureStage stage{*camera, *target, platform->description(), [&signals]() -> std::string {
                           while (const int signal = signals.next()) {
                               if (signal == SIGINT || signal == SIGTERM) {
                                   return signal == SIGINT ? "SIGINT" : "SIGTERM";
                               }
                               // SIGHUP reloads a bundle; a scan has none.
                           }
                           return {};
                       }};
    ScanReport report = runCapture(board, CaptureKind::kScan, folder, stage);
    report.cameraSetupMs = cameraSetupMs;
    report.displaySetupMs = displaySetupMs;
    report.seconds = msBetween(processStartNs, scanClockNs()) / 1000.0;
    return report;
}

std::string ScanReport::summaryLine() const {
    char taken[32];
    std::snprintf(taken, sizeof taken, "%.1f", scanSeconds);
    if (kind == CaptureKind::kRadiometry) {
        return "radiometry: " + std::to_string(radiometry.fields) + " flat fields, " +
               std::to_string(radiometry.tally.captures) + " captures (" +
               std::to_string(radiometry.tally.retried) + " retried) in " + taken + " s -> " +
               out.string() + " (" + camera.source + ", response " +
               responseName(radiometry.colour.response) + ", " +
               std::to_string(radiometry.colour.bits) + " bits)";
    }
    std::string line = "scan: " + std::to_string(patterns) + " patterns, " +
                       std::to_string(captures) + " captures (" + std::to_string(retried) +
                       " retried) in " + taken + " s -> " + out.string() + " (" + camera.source +
                       ", " + sizeText(camera.width, camera.height) + ", " +
                       std::to_string(camera.bits) + " bits); radiometry: ";
    if (!radiometry.captured) {
        return line + "none";
    }
    return line + std::to_string(radiometry.fields) + " flat fields, " +
           std::to_string(radiometry.tally.captures) + " captures (" +
           std::to_string(radiometry.tally.retried) + " retried), response " +
           responseName(radiometry.colour.response) + ", " +
           std::to_string(radiometry.colour.bits) + " bits";
}

std::string ScanReport::json() const {
    const nlohmann::ordered_json rejectedJson = rejectedJsonOf(rejected);
    nlohmann::ordered_json json = {
        {"out", out.string()},
        {"patterns", patterns},
        {"captures", captures},
        {"retried", retried},
        {"rejected", rejectedJson},
        {"projector",
         {{"width", projectorWidth},
          {"height", projectorHeight},
          {"phase_period", phasePeriod},
          {"phase_steps", phaseSteps}}},
        {"camera",
         {{"source", camera.source},
          {"description", camera.description},
          {"width", camera.width},
          {"height", camera.height},
          {"bits", camera.bits},
          {"exposure_us", camera.exposureUs},
          {"analogue_gain", camera.analogueGain}}},
        {"platform", platform},
        {"latency_ms", latencyMs},
        {"wait_ms", waitMs},
    };
    if (simulated) {
        json["simulated_latency_ms"] = simulatedLatencyMs;
    }
    json["lit_fraction"] = litFraction;
    json["noise_sigma"] = noiseSigma;
    json["setup_ms"] = {{"camera", cameraSetupMs}, {"display", displaySetupMs}};
    json["capture_ms"] = {{"p50", nearestRankPercentile(captureMs, 0.5)},
                          {"max", nearestRankPercentile(captureMs, 1.0)}};
    nlohmann::ordered_json radiometryJson = {{"captured", radiometry.captured}};
    if (!radiometry.captured) {
        radiometryJson["skipped"] = radiometry.skipped;
    } else {
        radiometryJson["out"] = (out / proto::kRadiometryFolderName).string();
        radiometryJson["fields"] = radiometry.fields;
        radiometryJson["captures"] = radiometry.tally.captures;
        radiometryJson["retried"] = radiometry.tally.retried;
        radiometryJson["rejected"] = rejectedJsonOf(radiometry.tally.rejected);
        radiometryJson["response"] = responseName(radiometry.colour.response);
        radiometryJson["bits"] = radiometry.colour.bits;
        radiometryJson["description"] = radiometry.colour.description;
        radiometryJson["lit_fraction"] = radiometry.litFraction;
        radiometryJson["capture_ms"] = {
            {"p50", nearestRankPercentile(radiometry.tally.captureMs, 0.5)},
            {"max", nearestRankPercentile(radiometry.tally.captureMs, 1.0)}};
        radiometryJson["seconds"] = radiometry.seconds;
    }
    json["radiometry"] = radiometryJson;
    json["scan_seconds"] = scanSeconds;
    json["seconds"] = seconds;
    return json.dump(2);
}

}  // namespace vpe::firmware
