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
#include <string>
#include <vector>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/light/light_rig.h"
#include "vpe/firmware/light/shared_light_publisher.h"
#include "vpe/firmware/loop/event_loop.h"
#include "vpe/firmware/loop/file_watch.h"
#include "vpe/firmware/loop/show_clock.h"
#include "vpe/firmware/player/frame_report.h"
#include "vpe/firmware/player/light_log.h"
#include "vpe/firmware/player/player_options.h"
#include "vpe/firmware/player/scene_slot.h"
#include "vpe/firmware/player/service_watchdog.h"
#include "vpe/proto/input_error.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::firmware {

// Bad input at start (board, bundle, display, sizes): vpe-player exits with status 2.
class PlayerInputError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

// The board's display: headless EGL, or KMS with the board's device, connector, mode and
// modesetting. Throws PlayerInputError (one line: the display is unavailable).
std::unique_ptr<renderer::gles::GraphicsPlatform> createDisplayPlatform(const BoardConfig& board);

// The last second of frames, for the node's status on the bus (firmware/bus/node_status.h).
struct FrameWindow {
    double fps = 0;         // frames drawn per second
    double frameP99Ms = 0;  // the 99th percentile of their draw times
    long skipped = 0;       // ticks with nothing new to draw
};

// The display lent to a task that needs it for a while (the control page's install steps: a
// scan's patterns): the player stops drawing, hands over its platform and the target it draws
// on, and draws again once the task returns.
struct DisplayLease {
    renderer::gles::GraphicsPlatform& platform;
    renderer::gles::RenderTarget& target;  // the player's own (KMS: the display's scanout)
    // Call between captures, at least a few times a second: the player's inputs and bus, its
    // status once a second and the watchdog go on. Returns why the task must stop ("SIGTERM",
    // "SIGINT"), empty to go on.
    std::function<std::string()> keepAlive;
};

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

    // Called about once a second from the loop, after lastWindow() is updated (the node's
    // status on the bus).
    void everySecond(std::function<void()> callback) { everySecond_ = std::move(callback); }
    const FrameWindow& lastWindow() const { return lastWindow_; }
    // Seconds since the process started.
    double uptimeSeconds() const;
    // The newest error line the player logged (a failed frame, a refused reload); empty: none.
    const std::string& lastError() const { return lastError_; }
    // "systemd 10 s" (the watchdog's interval), "systemd, no watchdog", "off (not under
    // systemd)".
    std::string watchdogState() const;
    // Black on screen while on (the control page's blackout, for the staff); the light and the
    // inputs go on underneath.
    void setBlackout(bool on);
    bool blackout() const { return blackout_; }
    // The bundle's file name, and its header's CRC-32 as "0x1a2b3c4d".
    std::string bundleName() const { return options_.bundle.filename().string(); }
    std::string bundleChecksum() const;
    // The preset on show.
    std::string presetName() { return scene_->renderer().presetName(); }

    // Runs `task` at the next turn of the loop with the display lent to it (DisplayLease), then
    // draws again. One at a time: false (and nothing queued) while another is queued or runs.
    bool lendDisplay(std::function<void(DisplayLease&)> task);
    bool displayLent() const { return static_cast<bool>(leaseTask_) || leaseRunning_; }

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
    // Clears the target to black and presents it (blackout).
    void renderBlack(std::int64_t beginNs);
    void closeWindow(std::int64_t nowNs);
    // A frame tick with nothing changed: no drawing, no presenting; the watchdog is fed.
    void skipFrame(std::int64_t nowNs);
    void applyEvents(std::vector<InputEvent>& events);
    // The inputs' and the rig's refusals into report_ (refusedByReason, eventsRefused), and the
    // inputs' counters.
    void collectRefusals();
    // When a frame starting now is expected on screen, on the show's clock.
    std::int64_t presentationTime() const;
    void reload(const char* why);
    // Runs leaseTask_ (the display lent), then makes the next tick draw.
    void runLease();
    // DisplayLease::keepAlive.
    std::string keepAliveDuringLease();
    // The once-a-second status window (everySecond_).
    void tickWindow(std::int64_t nowNs);
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
    bool blackout_ = false;
    std::string lastError_;
    std::function<void()> everySecond_;
    FrameWindow lastWindow_;
    std::vector<double> windowFrameMs_;  // this second's draw times
    long windowSkipped_ = 0;
    std::int64_t windowStartNs_ = 0;
    std::int64_t firstFrameNs_ = 0;
    std::function<void(DisplayLease&)> leaseTask_;
    bool leaseRunning_ = false;
    bool reloadAfterLease_ = false;  // a SIGHUP during the lease: reload once it ends
};

}  // namespace vpe::firmware
