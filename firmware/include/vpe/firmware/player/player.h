// SPDX-License-Identifier: MIT
// Player: vpe-player's running state. One EventLoop (loop/event_loop.h) waits on every input
// device's descriptors, the frame clock (a timer headless, page flips on KMS), signals and the
// bundle's file watch; between frames the inputs' events move the LightRig, and each frame
// renders the rig's light with the GlesFrameRenderer. SIGHUP or a replaced bundle file reloads
// the bundle; a bad new bundle is refused and the old one keeps playing.
//
// Each frame shows the light at its presentation time (when the frame is expected on screen:
// the frame start plus one frame period) on the show's clock: CLOCK_MONOTONIC alone,
// CLOCK_REALTIME for a node of a multi-node show, whose nodes then draw the same light for the
// same moment (firmware/bus/). What this node's own inputs change goes to the publisher.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/firmware/board_config.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/light/light_rig.h"
#include "vpe/firmware/light/shared_light_publisher.h"
#include "vpe/firmware/loop/event_loop.h"
#include "vpe/firmware/loop/file_watch.h"
#include "vpe/firmware/loop/service_watchdog.h"
#include "vpe/firmware/loop/show_clock.h"
#include "vpe/firmware/player/frame_report.h"
#include "vpe/firmware/player/light_log.h"
#include "vpe/firmware/player/scene_slot.h"
#include "vpe/firmware/player_options.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::firmware {

// Bad input at start (board, bundle, display, sizes): vpe-player exits with status 2.
class PlayerInputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The board's display: headless EGL, or KMS with the board's device, connector, mode and
// modesetting. Throws PlayerInputError (one line: the display is unavailable).
std::unique_ptr<renderer::gles::GraphicsPlatform> createDisplayPlatform(const BoardConfig& board);

class Player {
public:
    // Opens the platform, the bundle and the render target (and --light-log's file). `clock`:
    // the light rig's (ShowClock, realtime for a shared light). Throws PlayerInputError.
    Player(const PlayerOptions& options, const BoardConfig& board, std::int64_t processStartNs,
           ShowClock clock = ShowClock());
    ~Player();

    // Adds an input; its descriptors join the loop. Call before run().
    void addInput(std::unique_ptr<InputDevice> device);
    // Where the rig's state goes after this node's own inputs changed it (borrowed: an input
    // added with addInput, the bus).
    void setPublisher(SharedLightPublisher* publisher) { publisher_ = publisher; }
    // run() also stops once this returns true (checked after each frame): a replay's end.
    void stopWhen(std::function<bool()> condition, std::string reason);

    // Called after each successful reload (inputs that know the bundle's presets).
    void onBundleReloaded(std::function<void()> callback) {
        reloaded_.push_back(std::move(callback));
    }

    // Plays until --frames, a stop condition, SIGTERM or SIGINT.
    FrameReport run();

    const proto::BundleView& bundle() const { return scene_->view(); }
    // The light's sphere of a bundle (its mesh's centre, its viewer's azimuth 0).
    static LightSphere sphereOf(const proto::BundleView& view);
    const LightRig& rig() const { return rig_; }
    const FrameReport& report() const { return report_; }
    const ShowClock& clock() const { return clock_; }

private:
    void renderFrame();
    // A frame tick with nothing changed: no drawing, no presenting; the watchdog is fed.
    void skipFrame(std::int64_t nowNs);
    void applyEvents(std::vector<InputEvent>& events);
    // The inputs' and the rig's refusals into report_ (refusedByReason, eventsRefused), and the
    // inputs' counters.
    void collectRefusals();
    // When a frame starting now is expected on screen, on the show's clock.
    std::int64_t presentationTime() const;
    void reload(const char* why);
    // The rig's preset becomes the one the renderer shows (at start and after a reload).
    void adoptRenderersPreset();

    PlayerOptions options_;
    BoardConfig board_;
    std::int64_t processStartNs_;
    ShowClock clock_;
    bool headless_;
    std::unique_ptr<renderer::gles::GraphicsPlatform> platform_;
    std::unique_ptr<SceneSlot> scene_;
    std::unique_ptr<renderer::gles::RenderTarget> target_;
    LightRig rig_;
    EventLoop loop_;
    SignalWatch signals_;
    MonotonicTimer frameClock_;
    std::optional<FileWatch> bundleWatch_;
    ServiceWatchdog watchdog_;
    std::vector<std::unique_ptr<InputDevice>> devices_;
    SharedLightPublisher* publisher_ = nullptr;
    std::optional<LightLog> lightLog_;
    // One frame period: headless the timer's (0 unpaced), KMS measured between page flips.
    std::int64_t framePeriodNs_ = 0;
    std::int64_t lastFlipNs_ = 0;
    std::vector<InputEvent> pending_;
    std::vector<std::int64_t> unshownEvents_;  // timestamps applied since the last frame
    std::vector<std::function<void()>> reloaded_;
    std::function<bool()> stopCondition_;
    std::string stopReason_;
    FrameReport report_;
    std::uint64_t rigRefusals_ = 0;  // events the light rig refused (a preset out of range)
    bool running_ = true;
    bool frameDue_ = true;
    bool waitingForFlip_ = false;
    int shownPreset_ = -1;
    // What the frame on show was drawn for: a tick with the same light, no preset fade and no
    // new scene draws nothing (skipUnchanged_, off when unpaced).
    std::optional<std::array<float, 3>> shownLight_;
    bool sceneChanged_ = true;
    bool skipUnchanged_ = true;
    bool skipClockArmed_ = false;
    // While skipping on KMS no page flip paces the loop: this clock does.
    static constexpr double kSkipClockHz = 60.0;
    long consecutiveErrors_ = 0;
    std::int64_t firstFrameNs_ = 0;
};

}  // namespace vpe::firmware
