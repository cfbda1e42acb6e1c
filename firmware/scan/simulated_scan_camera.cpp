// SPDX-License-Identifier: MIT
// SimulatedScanCamera: the displayed pattern through ProcamSimulator.
#include "vpe/firmware/scan/simulated_scan_camera.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "vpe/firmware/player/player.h"

namespace vpe::firmware {

namespace procam = renderer::procam;

namespace {

constexpr std::size_t kHistory = 16;  // patterns remembered: far more than a latency spans

std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

}  // namespace

SimulatedScanCamera::SimulatedScanCamera(const std::filesystem::path& sceneFile, double latencyMs)
    : sceneFile_(sceneFile),
      scene_(procam::readSceneFile(sceneFile)),
      latencyNs_(static_cast<std::int64_t>(latencyMs * 1e6)) {
    if (!scene_.camera.monochrome) {
        throw PlayerInputError(sceneFile.string() +
                               ":camera.monochrome: false; a scan's camera records luminance "
                               "(set it to true)");
    }
    try {
        simulator_ = std::make_unique<procam::ProcamSimulator>(scene_.scene, scene_.camera);
    } catch (const std::invalid_argument& error) {
        throw PlayerInputError(sceneFile.string() + ": " + error.what());
    }
    const proto::PinholeCamera& camera = scene_.camera.camera;
    info_.source = "simulated:" + sceneFile.string();
    info_.width = camera.width;
    info_.height = camera.height;
    info_.bits = scene_.camera.bits;
    info_.exposureUs = 0;
    info_.analogueGain = 1;
    info_.description = "simulated camera (" + sceneFile.string() + ": " +
                        std::to_string(camera.width) + "x" + std::to_string(camera.height) + ", " +
                        std::to_string(scene_.camera.bits) + " bits; projector latency " +
                        numberText(latencyMs) + " ms)";
}

SimulatedScanCamera::~SimulatedScanCamera() = default;

int SimulatedScanCamera::projectorWidth() const {
    return scene_.scene.projector.camera.width;
}

int SimulatedScanCamera::projectorHeight() const {
    return scene_.scene.projector.camera.height;
}

void SimulatedScanCamera::patternShown(const std::vector<std::uint8_t>& rgba, int width, int height,
                                       std::int64_t shownNs) {
    if (width != projectorWidth() || height != projectorHeight() ||
        rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        throw std::invalid_argument("simulated camera: a " + std::to_string(width) + "x" +
                                    std::to_string(height) + " display for a " +
                                    std::to_string(projectorWidth()) + "x" +
                                    std::to_string(projectorHeight()) + " projector");
    }
    // Each channel as the display holds it: the projector throws what is on screen, not what
    // the scan meant to show.
    Shown shown{renderer::RgbImage(width, height), shownNs};
    for (std::size_t i = 0; i < shown.levels.pixelCount(); ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            shown.levels.values[3 * i + c] = static_cast<float>(rgba[4 * i + c]) / 255.0f;
        }
    }
    shown_.push_back(std::move(shown));
    if (shown_.size() > kHistory) {
        shown_.pop_front();
    }
}

ColourCapture SimulatedScanCamera::colourCapture() const {
    const procam::SimulatedCamera& camera = scene_.camera;
    ColourCapture colour;
    colour.bits = camera.bits;
    if (camera.response == procam::CameraResponse::kLinear) {
        colour.response = proto::CameraResponseKind::kLinear;
        colour.description =
            "simulated colour sensor, linear, " + std::to_string(camera.bits) + " bits";
        return colour;
    }
    colour.response = proto::CameraResponseKind::kUnknown;
    if (camera.bits != 8) {
        colour.unavailable = sceneFile_.string() + ":camera: a gamma response at " +
                             std::to_string(camera.bits) +
                             " bits; a camera response that is not linear is measured with an "
                             "8-bit bracket (set camera.bits = 8, or camera.response = "
                             "\"linear\")";
        return colour;
    }
    colour.description =
        "simulated colour sensor, gamma (response unknown: a bracketed ramp), 8 bits";
    return colour;
}

CameraImage SimulatedScanCamera::capture(std::int64_t notBeforeNs, const CaptureRequest& request) {
    sleepUntilNs(notBeforeNs);
    const std::int64_t startNs = scanClockNs();
    // The newest pattern the projector has had time to show; before any, it shows black.
    const Shown* visible = nullptr;
    for (auto it = shown_.rbegin(); it != shown_.rend(); ++it) {
        if (it->shownNs + latencyNs_ <= startNs) {
            visible = &*it;
            break;
        }
    }
    const renderer::RgbImage black(projectorWidth(), projectorHeight());
    const std::uint64_t number = captures_++;
    const renderer::RgbImage radiance =
        simulator_->radiance(visible ? visible->levels : black, number);
    procam::CameraFrame frame;
    if (request.colour || request.exposureScale != 1.0) {
        procam::SimulatedCamera sensor = scene_.camera;
        sensor.monochrome = !request.colour;
        sensor.exposure = scene_.camera.exposure * request.exposureScale;
        frame = simulator_->expose(radiance, number, sensor);
    } else {
        frame = simulator_->expose(radiance, number);
    }
    CameraImage image;
    image.width = frame.width;
    image.height = frame.height;
    image.channels = frame.channels;
    image.maxValue = frame.maxValue();
    image.samples = std::move(frame.samples);
    return image;
}

}  // namespace vpe::firmware
