// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/board_check.h"

#include <filesystem>
#include <optional>
#include <sstream>

#include "vpe/firmware/player/input_setup.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/tracking/lamp_calibration.h"
#include "vpe/proto/bundle.h"

namespace vpe::firmware {

namespace {

std::string presence(const std::filesystem::path& path) {
    std::error_code error;
    return std::filesystem::exists(path, error) ? "present" : "absent on this machine";
}

std::string number(double value) {
    std::ostringstream text;
    text << value;
    return text.str();
}

std::string range(const std::pair<double, double>& r) {
    std::ostringstream text;
    text << "[" << r.first << ", " << r.second << "]";
    return text.str();
}

}  // namespace

std::string checkBoard(const BoardConfig& board, const PlayerOptions& options) {
    InputSettings inputs;
    try {
        inputs = readInputSettings(board);
        if (inputs.camera && !inputs.camera->calibration.empty()) {
            LampCalibration::fit(inputs.camera->calibration);
        }
    } catch (const CalibrationError& error) {
        throw PlayerInputError(board.source + ":camera.calibration: " + error.what());
    }
    // The bundle, when given, is opened first: its camera may be what maps the lamp.
    std::optional<proto::BundleFile> bundle;
    if (!options.bundle.empty()) {
        bundle.emplace(proto::BundleFile::open(options.bundle));
    }
    std::ostringstream out;
    out << board.source << ": valid board file";
    if (!board.name.empty()) {
        out << " (" << board.name << ")";
    }
    out << "\n";
    if (board.display.backend == DisplayBackend::kHeadless) {
        out << "  display: headless (EGL surfaceless), "
            << (board.render.rate > 0 ? number(board.render.rate) + " Hz timer"
                                      : std::string("unpaced"))
            << "\n";
    } else {
        out << "  display: kms " << board.display.device << " ("
            << (board.display.device == "auto" ? std::string("first connected card")
                                               : presence(board.display.device))
            << "), connector " << board.display.connector << ", mode "
            << (board.display.mode ? std::to_string(board.display.mode->width) + "x" +
                                         std::to_string(board.display.mode->height)
                                   : std::string("preferred"))
            << ", " << (board.display.atomic ? "atomic if available" : "legacy") << "\n";
    }
    if (inputs.knobs && inputs.knobs->enabled) {
        const std::string& chip = inputs.knobs->chip;
        const std::filesystem::path node = chip.find('/') != std::string::npos
                                               ? std::filesystem::path(chip)
                                               : std::filesystem::path("/dev") / chip;
        out << "  knobs: " << inputs.knobs->encoders.size() << " encoders, "
            << inputs.knobs->buttons.size() << " buttons on " << chip << " (" << presence(node)
            << ")\n";
    } else {
        out << "  knobs: off\n";
    }
    if (inputs.camera && inputs.camera->enabled) {
        out << "  camera: " << inputs.camera->id << ", " << inputs.camera->tracking.width << "x"
            << inputs.camera->tracking.height << ", ";
        if (!inputs.camera->calibration.empty()) {
            out << inputs.camera->calibration.size() << " calibration points (fit ok";
        } else if (bundle) {
            out << "the lamp mapped by "
                << describeLampDirectionMap(
                       lampDirectionFor(*inputs.camera, inputs, bundle->view()))
                << " (";
        } else {
            out << "no calibration table: the lamp needs the bundle's camera (not checked "
                   "without --bundle";
        }
        out << "; the camera itself is probed when the player starts)\n";
    } else {
        out << "  camera: off\n";
    }
    if (board.scan) {
        const ScanConfig& scan = *board.scan;
        out << "  scan: ";
        if (scan.simulate) {
            out << "simulated camera " << scan.simulate->string()
                << (std::filesystem::exists(*scan.simulate) ? "" : " (absent)");
        } else {
            out << "camera " << (inputs.camera ? inputs.camera->id : std::string("(no [camera])"))
                << (inputs.camera && inputs.camera->enabled ? "" : " (disabled: --scan refuses)")
                << ", still " << scan.cameraWidth << "x" << scan.cameraHeight << ", exposure "
                << scan.exposureUs << " us, gain " << scan.analogueGain;
        }
        out << "; latency " << scan.latencyMs << " ms, " << scan.retries << " retries, period "
            << scan.phasePeriod << ", " << scan.phaseSteps << " steps\n";
    } else {
        out << "  scan: none (no [scan] section)\n";
    }
    if (inputs.osc && inputs.osc->enabled) {
        out << "  osc: udp " << inputs.osc->address << ":" << inputs.osc->port << "\n";
    } else {
        out << "  osc: off\n";
    }
    if (inputs.bus && inputs.bus->enabled) {
        const bus::BusConfig& bus = *inputs.bus;
        out << "  bus: " << (bus.tls() ? "mqtts://" : "mqtt://")
            << (bus.host.find(':') == std::string::npos ? bus.host : "[" + bus.host + "]") << ":"
            << bus.port << ", topic " << bus.topic() << ", " << bus::busRoleName(bus.role) << " \""
            << bus.clientId << "\", "
            << (bus.username.empty() ? std::string("no credentials")
                                     : "user \"" + bus.username + "\"" +
                                           (bus.password.empty() ? "" : " with a password"))
            << (bus.tls() ? ", TLS with " + bus.cafile->string() : std::string(", no TLS"))
            << "; the clock shared with the other nodes: CLOCK_REALTIME (chrony)\n";
    } else {
        out << "  bus: off\n";
    }
    out << "  light: azimuth " << range(board.light.limits.azimuthDeg) << "°, elevation "
        << range(board.light.limits.elevationDeg) << "°, distance "
        << (board.light.limits.distanceM ? range(*board.light.limits.distanceM) + " m"
                                         : std::string("[0.5, 4] × object radius"))
        << ", smoothing " << board.light.smoothingSeconds << " s\n";
    out << "  idle: "
        << (board.idle.enabled
                ? "after " + number(board.idle.quietSeconds) + " s quiet, figure of eight every " +
                      number(board.idle.periodSeconds) + " s"
                : std::string("off"))
        << "\n";
    if (bundle) {
        const auto& projector = bundle->view().projector();
        const auto& camera = bundle->view().camera();
        out << "  bundle: " << options.bundle.string() << " ok (checksum verified), projector "
            << projector.width << "x" << projector.height << ", " << bundle->view().presets().size()
            << " presets, "
            << (camera ? "camera " + std::to_string(camera->width) + "x" +
                             std::to_string(camera->height)
                       : std::string("no camera"))
            << "\n";
        const auto w = static_cast<int>(projector.width), h = static_cast<int>(projector.height);
        // The size the board fixes, if any: the headless render size or the KMS mode.
        const bool headless = board.display.backend == DisplayBackend::kHeadless;
        std::optional<DisplayMode> fixed = board.display.mode;
        if (headless) {
            fixed.reset();
            if (board.render.width) {
                fixed = DisplayMode{*board.render.width, *board.render.height, 0};
            }
        }
        if (fixed && (fixed->width != w || fixed->height != h)) {
            throw PlayerInputError(
                board.source + ":" + (headless ? "render.size" : "display.mode") + ": " +
                std::to_string(fixed->width) + "x" + std::to_string(fixed->height) +
                " differs from the bundle's projector " + std::to_string(w) + "x" +
                std::to_string(h));
        }
    }
    return out.str();
}

}  // namespace vpe::firmware
