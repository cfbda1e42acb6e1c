// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/player.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include <poll.h>

#include "vpe/firmware/player/player_log.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/renderer/gles/headless_egl_platform.h"
#include "vpe/renderer/gles/kms_platform.h"
#include "vpe/renderer/gles/target_drawing.h"

namespace vpe::firmware {

namespace gles = renderer::gles;

namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;
// A GPU that fails this many frames in a row is not coming back: exit (status 1) and let the
// service manager restart the player.
constexpr long kMaxConsecutiveErrors = 120;

double msBetween(std::int64_t fromNs, std::int64_t toNs) {
    return static_cast<double>(toNs - fromNs) / static_cast<double>(kNsPerMs);
}

// Checked before the platform opens a device, so that a misuse is named rather than a missing
// display.
std::unique_ptr<gles::GraphicsPlatform> createPlatform(const BoardConfig& board,
                                                       const PlayerOptions& options) {
    if (options.out && board.display.backend != DisplayBackend::kHeadless) {
        throw PlayerInputError("--out: frames are read back only on the headless display (" +
                               options.board.string() + " uses kms)");
    }
    return createDisplayPlatform(board);
}

}  // namespace

std::unique_ptr<gles::GraphicsPlatform> createDisplayPlatform(const BoardConfig& board) {
    try {
        if (board.display.backend == DisplayBackend::kHeadless) {
            return gles::createHeadlessEglPlatform();
        }
        gles::KmsOptions kms;
        kms.device = board.display.device;
        kms.connector = board.display.connector;
        kms.atomic = board.display.atomic;
        if (board.display.mode) {
            kms.modeWidth = board.display.mode->width;
            kms.modeHeight = board.display.mode->height;
            kms.modeRefresh = board.display.mode->refresh;
        }
        return gles::createKmsPlatform(kms);
    } catch (const gles::GraphicsError& error) {
        throw PlayerInputError(error.what());
    }
}

LightSphere Player::sphereOf(const proto::BundleView& view) {
    return LightSphere(view.mesh().positions, view.settings().viewerPosition);
}

Player::Player(const PlayerOptions& options, const BoardConfig& board, std::int64_t processStartNs,
               ShowClock clock)
    : options_(options),
      board_(board),
      processStartNs_(processStartNs),
      clock_(clock),
      headless_(board.display.backend == DisplayBackend::kHeadless),
      platform_(createPlatform(board, options)),
      scene_(SceneSlot::load(options.bundle, options.preset)),
      rig_(board.light, board.idle, sphereOf(scene_->view()),
           static_cast<int>(scene_->view().presets().size()), clock_.nowNs()) {
    gles::GlesFrameRenderer& renderer = scene_->renderer();
    // The renderer draws the projector's frame at its calibrated size: the target must match.
    int width = renderer.width(), height = renderer.height();
    if (options_.width) {
        width = *options_.width;
        height = *options_.height;
    } else if (headless_ && board_.render.width) {
        width = *board_.render.width;
        height = *board_.render.height;
    }
    if (width != renderer.width() || height != renderer.height()) {
        throw PlayerInputError(
            (options_.width ? std::string("--size") : options_.board.string() + ":render.size") +
            ": " + std::to_string(width) + "x" + std::to_string(height) +
            " differs from the bundle's projector " + std::to_string(renderer.width()) + "x" +
            std::to_string(renderer.height()));
    }
    try {
        target_ = platform_->createRenderTarget(width, height);
    } catch (const gles::GraphicsError& error) {
        throw PlayerInputError(error.what());
    }
    if (options_.out) {
        std::error_code error;
        std::filesystem::create_directories(*options_.out, error);
        if (error || !std::filesystem::is_directory(*options_.out)) {
            throw PlayerInputError(options_.out->string() + ": cannot create the output folder (" +
                                   (error ? error.message() : "not a folder") + ")");
        }
    }
    if (options_.lightLog) {
        lightLog_.emplace(*options_.lightLog);
    }
    adoptRenderersPreset();
    report_.width = width;
    report_.height = height;
    report_.platform = platform_->description();

    loop_.watch(signals_.fd(), [this] {
        while (const int signal = signals_.next()) {
            if (signal == SIGHUP) {
                reload("SIGHUP");
            } else {
                running_ = false;
                report_.stoppedBy = signal == SIGTERM ? "SIGTERM" : "SIGINT";
            }
        }
    });
    try {
        bundleWatch_.emplace(options_.bundle);
        loop_.watch(bundleWatch_->fd(), [this] {
            if (bundleWatch_->changed()) {
                reload("file replaced");
            }
        });
    } catch (const EventLoopError& error) {
        playerLog(std::string(error.what()) + "; reload with SIGHUP only");
    }
    const double rate = options_.rate.value_or(board_.render.rate);
    if (clock_.shared()) {
        // Every node shows a change from the same frame on: the publisher's next one.
        rig_.setMoveLead(
            static_cast<std::int64_t>(1e9 / (headless_ && rate > 0 ? rate : kSkipClockHz)));
    }
    // Unpaced (headless, rate 0: a benchmark) every tick draws; paced, a tick whose light,
    // preset and scene equal the frame on show draws nothing.
    skipUnchanged_ = !(headless_ && rate <= 0);
    if (!headless_) {
        framePeriodNs_ = static_cast<std::int64_t>(1e9 / kSkipClockHz);  // until flips measure it
        loop_.watch(target_->vsyncDescriptor(), [this] {
            if (target_->onVsyncReadable()) {
                waitingForFlip_ = false;
                frameDue_ = true;
                // Back-to-back flips measure the display's refresh period (a 50 Hz projector).
                const std::int64_t now = monotonicNowNs();
                const std::int64_t interval = now - lastFlipNs_;
                if (lastFlipNs_ != 0 && interval > 5 * kNsPerMs && interval < 40 * kNsPerMs) {
                    framePeriodNs_ += (interval - framePeriodNs_) / 8;
                }
                lastFlipNs_ = now;
            }
        });
        // No flip comes while frames are skipped: this clock ticks at the display's pace then.
        loop_.watch(frameClock_.fd(), [this] {
            if (frameClock_.expirations() > 0 && !waitingForFlip_) {
                frameDue_ = true;
            }
        });
    } else if (rate > 0) {
        framePeriodNs_ = static_cast<std::int64_t>(1e9 / rate);
        frameClock_.arm(monotonicNowNs(), framePeriodNs_);
        frameDue_ = false;
        loop_.watch(frameClock_.fd(), [this] {
            if (frameClock_.expirations() > 0) {
                frameDue_ = true;  // late frames are dropped, not queued
            }
        });
    }
}

Player::~Player() = default;

void Player::addInput(std::unique_ptr<InputDevice> device) {
    InputDevice* raw = device.get();
    for (const int fd : raw->pollDescriptors()) {
        loop_.watch(fd, [this, raw, fd] { raw->onReadable(fd, monotonicNowNs(), pending_); });
    }
    devices_.push_back(std::move(device));
}

void Player::stopWhen(std::function<bool()> condition, std::string reason) {
    stopCondition_ = std::move(condition);
    stopReason_ = std::move(reason);
}

void Player::applyEvents(std::vector<InputEvent>& events) {
    if (events.empty()) {
        return;
    }
    const std::int64_t revision = rig_.revisionNs();
    bool localChange = false;
    for (const InputEvent& event : events) {
        // The rig runs on the show's clock; latency is measured on the inputs' own.
        InputEvent onShowClock = event;
        onShowClock.timestampNs = clock_.fromMonotonic(event.timestampNs);
        const std::int64_t before = rig_.revisionNs();
        if (rig_.apply(onShowClock)) {
            unshownEvents_.push_back(event.timestampNs);
            ++report_.events[inputSourceName(event.source)];
            localChange =
                localChange || (event.source != InputSource::kBus && rig_.revisionNs() != before);
        } else {
            ++rigRefusals_;
        }
    }
    events.clear();
    // What this node's own inputs did goes to the other nodes (another node's state is theirs
    // already).
    if (publisher_ != nullptr && localChange && rig_.revisionNs() != revision) {
        publisher_->offer(rig_.shared(), monotonicNowNs());
    }
}

std::int64_t Player::presentationTime() const {
    return clock_.nowNs() + framePeriodNs_;
}

void Player::collectRefusals() {
    report_.refusedByReason.clear();
    if (rigRefusals_ > 0) {
        report_.refusedByReason["light.preset_out_of_range"] = rigRefusals_;
    }
    for (const auto& device : devices_) {
        for (const auto& [reason, count] : device->refusals()) {
            report_.refusedByReason[reason] += count;
        }
    }
    report_.eventsRefused = 0;
    for (const auto& [reason, count] : report_.refusedByReason) {
        report_.eventsRefused += static_cast<long>(count);
    }
    report_.counters.clear();
    for (const auto& device : devices_) {
        for (const auto& [name, count] : device->counters()) {
            report_.counters[name] += count;
        }
    }
    if (rig_.staleStates() > 0) {
        report_.counters["light.stale_states"] = rig_.staleStates();
    }
}

void Player::reload(const char* why) {
    watchdog_.reloading();
    try {
        const std::string preset = scene_->renderer().presetName();
        std::unique_ptr<SceneSlot> next = SceneSlot::load(options_.bundle, "");
        if (next->renderer().width() != target_->width() ||
            next->renderer().height() != target_->height()) {
            throw SceneLoadError(options_.bundle.string() + ": projector " +
                                 std::to_string(next->renderer().width()) + "x" +
                                 std::to_string(next->renderer().height()) + " differs from " +
                                 std::to_string(target_->width()) + "x" +
                                 std::to_string(target_->height()));
        }
        // Keep the preset by name when the new bundle has it.
        if (next->presetIndex(preset) >= 0) {
            next->renderer().selectPreset(preset);
        }
        scene_ = std::move(next);
        rig_.rebase(sphereOf(scene_->view()), static_cast<int>(scene_->view().presets().size()));
        adoptRenderersPreset();
        ++report_.reloads;
        playerLog(options_.bundle.string() + ": reloaded (" + why + ")");
        for (const auto& callback : reloaded_) {
            callback();
        }
    } catch (const SceneLoadError& error) {
        ++report_.reloadsRefused;
        lastError_ = std::string(error.what()) + "; reload (" + why +
                     ") refused, still playing the previous bundle";
        playerLog(lastError_);
    }
    sceneChanged_ = true;
    watchdog_.reloaded("playing " + options_.bundle.string());
}

void Player::adoptRenderersPreset() {
    shownPreset_ = scene_->presetIndex(scene_->renderer().presetName());
    rig_.apply({InputSource::kIdle, 0, SelectPreset{shownPreset_, false}});
}

void Player::renderFrame() {
    const std::int64_t beginNs = monotonicNowNs();
    const std::int64_t presentationNs = presentationTime();
    rig_.advance(presentationNs);
    if (rig_.preset() != shownPreset_) {
        const auto& presets = scene_->view().presets();
        scene_->renderer().selectPreset(
            std::string(presets[static_cast<std::size_t>(rig_.preset())].name));
        shownPreset_ = rig_.preset();
    }
    const std::array<float, 3> light = rig_.position();
    // Blackout: the light goes on underneath; the first black frame draws, the rest skip.
    const bool unchanged = skipUnchanged_ && !sceneChanged_ &&
                           (blackout_ || (shownLight_ == light && !scene_->renderer().animating()));
    if (lightLog_) {
        lightLog_->record(clock_.toRealtime(presentationNs), rig_.current(),
                          inputSourceName(rig_.activeSource()), !unchanged);
    }
    if (unchanged) {
        skipFrame(beginNs);
        return;
    }
    if (!headless_) {
        frameClock_.disarm();  // page flips pace the frames again
        skipClockArmed_ = false;
    }
    if (blackout_) {
        renderBlack(beginNs);
        return;
    }
    gles::FrameInputs inputs;
    const proto::RenderSettings& settings = scene_->view().settings();
    inputs.lightPosition = light;
    const auto intensity = static_cast<float>(board_.light.intensity);
    inputs.lightIntensity = {intensity, intensity, intensity};
    inputs.inverseSquare = board_.light.inverseSquare;
    inputs.referenceDistance =
        static_cast<float>(rig_.limits().distanceM->first + rig_.limits().distanceM->second) * 0.5f;
    inputs.gain = settings.gain;
    inputs.timeSeconds = static_cast<double>(beginNs) * 1e-9;
    try {
        scene_->renderer().render(*target_, inputs);
        target_->present();  // headless: glFinish, the frame is done
        if (!headless_) {
            // Paced by the flip: the next frame when its event arrives (the first frame's
            // modeset is synchronous, so no event comes for it).
            waitingForFlip_ = target_->vsyncPending();
            frameDue_ = !waitingForFlip_;
        }
        consecutiveErrors_ = 0;
    } catch (const gles::DisplayLostError&) {
        throw;  // nothing more to draw on: the player stops with that one line
    } catch (const gles::GraphicsError& error) {
        ++report_.errors;
        if (consecutiveErrors_++ == 0) {
            lastError_ =
                std::string("frame ") + std::to_string(report_.frames) + ": " + error.what();
            playerLog(lastError_);
        }
        if (consecutiveErrors_ >= kMaxConsecutiveErrors) {
            throw;
        }
        if (!headless_) {
            // No flip was queued, so no event will come, and the frame clock was disarmed
            // above: try again at the skip clock's pace (an error that persists ends the
            // player after kMaxConsecutiveErrors tries, two seconds), not wait for the watchdog.
            waitingForFlip_ = false;
            const auto period = static_cast<std::int64_t>(1e9 / kSkipClockHz);
            frameClock_.arm(beginNs + period, period);
            skipClockArmed_ = true;
        }
        return;
    }
    const std::int64_t submittedNs = monotonicNowNs();
    shownLight_ = light;
    sceneChanged_ = false;
    windowFrameMs_.push_back(msBetween(beginNs, submittedNs));
    for (const std::int64_t eventNs : unshownEvents_) {
        report_.latencyMs.add(msBetween(eventNs, submittedNs));
    }
    unshownEvents_.clear();
    report_.frameMs.add(msBetween(beginNs, submittedNs));
    if (report_.frames == 0) {
        firstFrameNs_ = submittedNs;
        report_.firstFrameMs = msBetween(processStartNs_, submittedNs);
        report_.rssStartKb = residentKilobytes();
        watchdog_.ready("playing " + options_.bundle.string());
    }
    if (report_.frames == 1000) {
        report_.rssWarmKb = residentKilobytes();
    }
    report_.seconds = static_cast<double>(submittedNs - firstFrameNs_) * 1e-9;
    if (options_.out && report_.frames % options_.every == 0) {
        // Read back only to write it, after the frame is timed: a display scans the frame out
        // by itself (KMS: present() queued the flip and returned), no CPU copy is part of it.
        const std::vector<std::uint8_t> rgba = target_->readRgba8();
        std::vector<std::uint8_t> rgb(rgba.size() / 4 * 3);
        for (std::size_t p = 0; p < rgba.size() / 4; ++p) {
            std::memcpy(&rgb[3 * p], &rgba[4 * p], 3);  // alpha dropped
        }
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05ld.ppm", report_.frames);
        proto::writePnmAtomically(*options_.out / name, target_->width(), target_->height(), 3,
                                  rgb);
        ++report_.written;
    }
    ++report_.frames;
    watchdog_.frameDone(submittedNs);
}

void Player::skipFrame(std::int64_t nowNs) {
    // What is on show is what this frame would draw: events since the last frame changed
    // nothing visible, so they are shown now.
    for (const std::int64_t eventNs : unshownEvents_) {
        report_.latencyMs.add(msBetween(eventNs, nowNs));
    }
    unshownEvents_.clear();
    ++report_.skipped;
    ++windowSkipped_;
    watchdog_.frameDone(nowNs);
    if (!headless_ && !skipClockArmed_) {
        const auto period = static_cast<std::int64_t>(1e9 / kSkipClockHz);
        frameClock_.arm(nowNs + period, period);
        skipClockArmed_ = true;
    }
}

void Player::renderBlack(std::int64_t beginNs) {
    gles::clearToBlack(*target_);
    target_->present();
    if (!headless_) {
        waitingForFlip_ = target_->vsyncPending();
        frameDue_ = !waitingForFlip_;
    }
    const std::int64_t submittedNs = monotonicNowNs();
    sceneChanged_ = false;
    shownLight_.reset();  // the next lit frame draws
    unshownEvents_.clear();
    windowFrameMs_.push_back(msBetween(beginNs, submittedNs));
    ++report_.frames;
    watchdog_.frameDone(submittedNs);
}

void Player::setBlackout(bool on) {
    if (on != blackout_) {
        blackout_ = on;
        sceneChanged_ = true;  // the next tick draws: black, or the scene again
    }
}

double Player::uptimeSeconds() const {
    return static_cast<double>(monotonicNowNs() - processStartNs_) * 1e-9;
}

std::string Player::watchdogState() const {
    if (!watchdog_.underSystemd()) {
        return "off (not under systemd)";
    }
    if (watchdog_.intervalNs() <= 0) {
        return "systemd, no watchdog";
    }
    char text[48];
    std::snprintf(text, sizeof text, "systemd %.0f s",
                  static_cast<double>(watchdog_.intervalNs()) * 1e-9);
    return text;
}

std::string Player::bundleChecksum() const {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", scene_->view().header().checksum);
    return text;
}

void Player::closeWindow(std::int64_t nowNs) {
    const double seconds = static_cast<double>(nowNs - windowStartNs_) * 1e-9;
    lastWindow_.fps = seconds > 0 ? static_cast<double>(windowFrameMs_.size()) / seconds : 0;
    lastWindow_.frameP99Ms = nearestRankPercentile(windowFrameMs_, 0.99);
    lastWindow_.skipped = windowSkipped_;
    windowFrameMs_.clear();
    windowSkipped_ = 0;
    windowStartNs_ = nowNs;
}

void Player::tickWindow(std::int64_t nowNs) {
    if (nowNs - windowStartNs_ >= 1'000'000'000) {
        closeWindow(nowNs);
        if (everySecond_) {
            everySecond_();
        }
    }
}

bool Player::lendDisplay(std::function<void(DisplayLease&)> task) {
    if (displayLent()) {
        return false;
    }
    leaseTask_ = std::move(task);
    return true;
}

std::string Player::keepAliveDuringLease() {
    const std::int64_t now = monotonicNowNs();
    // Signals are read here, not by the loop: a reload waits until the display is back.
    while (const int signal = signals_.next()) {
        if (signal == SIGHUP) {
            reloadAfterLease_ = true;
        } else {
            running_ = false;
            report_.stoppedBy = signal == SIGTERM ? "SIGTERM" : "SIGINT";
        }
    }
    // The inputs' ticks service them (the bus reads, writes and reconnects there); what they
    // say moves the light underneath, as during a blackout.
    for (const auto& device : devices_) {
        device->onTick(now, pending_);
    }
    applyEvents(pending_);
    watchdog_.frameDone(now);
    tickWindow(now);
    return running_ ? std::string() : report_.stoppedBy;
}

void Player::runLease() {
    std::function<void(DisplayLease&)> task = std::move(leaseTask_);
    leaseTask_ = nullptr;
    // KMS: the frame on its way to the screen first, so that the task owns the flips.
    const int vsync = target_->vsyncDescriptor();
    while (vsync >= 0 && waitingForFlip_ && target_->vsyncPending()) {
        pollfd ready{vsync, POLLIN, 0};
        if (::poll(&ready, 1, 1000) <= 0) {
            break;  // no flip within a second: the task's own present() waits for it
        }
        if (target_->onVsyncReadable()) {
            break;
        }
    }
    waitingForFlip_ = false;
    leaseRunning_ = true;
    DisplayLease lease{*platform_, *target_, [this] { return keepAliveDuringLease(); }};
    try {
        task(lease);
    } catch (...) {
        leaseRunning_ = false;
        throw;
    }
    leaseRunning_ = false;
    platform_->makeCurrent();
    // The target holds whatever the task left there: the next tick draws the scene again.
    sceneChanged_ = true;
    shownLight_.reset();
    frameDue_ = true;
    if (!headless_) {
        frameClock_.disarm();
        skipClockArmed_ = false;
    }
    if (reloadAfterLease_) {
        reloadAfterLease_ = false;
        reload("SIGHUP");
    }
}

FrameReport Player::run() {
    const bool unpaced = headless_ && options_.rate.value_or(board_.render.rate) <= 0;
    windowStartNs_ = monotonicNowNs();
    windowFrameMs_.reserve(256);
    while (running_) {
        // Unpaced: look at the inputs and go on; paced: sleep until a descriptor is ready.
        loop_.runOnce(unpaced || frameDue_ ? 0 : -1);
        const std::int64_t now = monotonicNowNs();
        for (const auto& device : devices_) {
            device->onTick(now, pending_);
        }
        applyEvents(pending_);
        if (!running_) {
            break;
        }
        if ((frameDue_ || unpaced) && !waitingForFlip_) {
            frameDue_ = false;
            renderFrame();  // KMS: may set frameDue_ again
            if (options_.frames > 0 && report_.frames + report_.skipped >= options_.frames) {
                report_.stoppedBy = "frames";
                break;
            }
            if (stopCondition_ && stopCondition_()) {
                report_.stoppedBy = stopReason_;
                break;
            }
        }
        tickWindow(now);
        if (leaseTask_ && running_) {
            runLease();
        }
    }
    watchdog_.stopping();
    if (lightLog_) {
        lightLog_->flush();
    }
    report_.rssEndKb = residentKilobytes();
    collectRefusals();
    report_.preset = scene_->renderer().presetName();
    report_.azimuthDeg = rig_.current().azimuthDeg;
    report_.elevationDeg = rig_.current().elevationDeg;
    report_.distanceM = rig_.current().distanceM;
    report_.activeInput = inputSourceName(rig_.activeSource());
    return report_;
}

}  // namespace vpe::firmware
