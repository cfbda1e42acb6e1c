// SPDX-License-Identifier: MIT
// CaptureLoop: groups, retries with longer waits, and the wait that worked kept.
#include "vpe/firmware/scan/capture_loop.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "scan_time.h"

namespace vpe::firmware {

using scan_time::msBetween;
using scan_time::nsOf;
using scan_time::numberText;

CaptureLoop::CaptureLoop(PatternProjector& projector, ScanCamera& camera, Interrupted interrupted,
                         int width, int height, const CaptureTiming& timing)
    : projector_(projector),
      camera_(camera),
      interrupted_(std::move(interrupted)),
      width_(width),
      height_(height),
      timing_(timing),
      waitMs_(timing.latencyMs) {}

void CaptureLoop::stopOnSignal() {
    if (!interrupted_) {
        return;
    }
    if (const std::string why = interrupted_(); !why.empty()) {
        throw ScanError("scan: stopped by " + why + "; nothing written");
    }
}

void CaptureLoop::show(const Shot& shot, std::span<const std::uint8_t> codes,
                       std::int64_t& shownNs) {
    shownNs = shot.channels == 3 ? projector_.showRgb(codes) : projector_.show(codes);
    if (camera_.needsShownImage()) {
        camera_.patternShown(projector_.readBack(), width_, height_, shownNs);
    }
}

void CaptureLoop::showBlack(double ms) {
    const std::vector<std::uint8_t> black(static_cast<std::size_t>(width_) *
                                          static_cast<std::size_t>(height_));
    std::int64_t shownNs = 0;
    show(Shot{"black", 1, CaptureRequest{}}, black, shownNs);
    // In steps, so that the caller's bus and watchdog are served through a long settle.
    const std::int64_t endNs = shownNs + nsOf(ms);
    for (std::int64_t now = scanClockNs(); now < endNs; now = scanClockNs()) {
        sleepUntilNs(std::min(endNs, now + nsOf(100)));
        stopOnSignal();
    }
    stopOnSignal();
}

CaptureTally CaptureLoop::run(const std::vector<Shot>& shots, FrameCheck& check, const Draw& draw,
                              const Accept& accepted) {
    CaptureTally tally;
    std::vector<int> attempts(shots.size(), 0);
    const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    std::vector<std::uint8_t> codes;
    for (const std::vector<std::size_t>& group : check.groups()) {
        std::vector<CameraImage> images(group.size());
        FrameVerdict failure;
        std::size_t failedAt = group.front();
        bool passed = false;
        for (int attempt = 0; attempt <= timing_.retries && !passed; ++attempt) {
            const double wait = waitMs_ + attempt * timing_.retryWaitMs;
            failure = {};
            for (std::size_t k = 0; k < group.size() && failure.passed(); ++k) {
                const std::size_t index = group[k];
                const Shot& shot = shots.at(index);
                codes.resize(pixels * static_cast<std::size_t>(shot.channels));
                draw(index, codes);
                std::int64_t shownNs = 0;
                show(shot, codes, shownNs);
                images[k] = camera_.capture(shownNs + nsOf(wait), shot.request);
                tally.captureMs.push_back(msBetween(shownNs, scanClockNs()));
                ++tally.captures;
                ++attempts[index];
                stopOnSignal();
                failure = check.check(index, images[k]);
                if (!failure.passed()) {
                    ++tally.rejected[static_cast<std::size_t>(failure.problem)];
                    failedAt = index;
                }
            }
            if (failure.passed()) {
                passed = true;
                waitMs_ = wait;  // a projector slower than the board says is slow for every image
            }
        }
        if (!passed) {
            throw ScanError("scan: " + shots[failedAt].name + ": " + failure.detail + " (" +
                            std::to_string(attempts[failedAt]) + " captures, the last " +
                            numberText(waitMs_ + timing_.retries * timing_.retryWaitMs) +
                            " ms after the pattern; raise [scan] latency_ms or retries)");
        }
        for (std::size_t k = 0; k < group.size(); ++k) {
            tally.retried += attempts[group[k]] > 1 ? 1 : 0;
            accepted(group[k], images[k], attempts[group[k]]);
        }
    }
    return tally;
}

}  // namespace vpe::firmware
