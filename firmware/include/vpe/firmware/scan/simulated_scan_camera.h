// SPDX-License-Identifier: MIT
// SimulatedScanCamera: the scan's camera on a simulated installation (a scene file, as vpe
// synth-procam writes installation.toml). What the display really shows — read back from the
// headless render target — is what the simulated projector throws; ProcamSimulator renders
// what the camera records, with fresh noise per capture. A projector latency may be simulated:
// a capture starting sooner than it after a pattern change sees the pattern shown before, as a
// real projector that is slower than the board says would show it. The radiometric capture's
// colour frames come from the same optics through a colour copy of the scene's sensor (its
// exposure × the request's scale, its bits, noise and response): ProcamSimulator's expose with
// another sensor.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>

#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/procam/procam_simulator.h"
#include "vpe/renderer/procam/scene_file.h"

namespace vpe::firmware {

class SimulatedScanCamera final : public ScanCamera {
public:
    // Reads the scene file and traces the installation once (ProcamSimulator; all cores).
    // Throws PlayerInputError naming the file: unreadable, not simulable, or an RGB camera (a
    // scan's camera records luminance: camera.monochrome must be true).
    SimulatedScanCamera(const std::filesystem::path& sceneFile, double latencyMs);
    ~SimulatedScanCamera() override;

    const ScanCameraInfo& info() const override { return info_; }
    // Linear when the scene's camera response is linear; a gamma response is "unknown" and
    // needs 8 bits (unavailable at 10: the bracket reads 8-bit codes).
    ColourCapture colourCapture() const override;
    bool needsShownImage() const override { return true; }
    void patternShown(const std::vector<std::uint8_t>& rgba, int width, int height,
                      std::int64_t shownNs) override;
    // Sleeps until notBeforeNs, then exposes what the projector shows then; the simulator's
    // frame number is the capture's index in the run (0, 1, …), so noise differs between
    // captures and a test can render the same frame.
    CameraImage capture(std::int64_t notBeforeNs, const CaptureRequest& request) override;

    int projectorWidth() const;
    int projectorHeight() const;
    const renderer::procam::ProcamSimulator& simulator() const { return *simulator_; }

private:
    struct Shown {
        renderer::RgbImage levels;  // drive levels in [0, 1], three per projector pixel
        std::int64_t shownNs = 0;
    };

    std::filesystem::path sceneFile_;
    renderer::procam::SceneFile scene_;
    std::unique_ptr<renderer::procam::ProcamSimulator> simulator_;
    ScanCameraInfo info_;
    std::int64_t latencyNs_ = 0;
    std::deque<Shown> shown_;  // oldest first
    std::uint64_t captures_ = 0;
};

}  // namespace vpe::firmware
