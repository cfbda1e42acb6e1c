// SPDX-License-Identifier: MIT
// The scan's clock: CLOCK_MONOTONIC, as libcamera's sensor timestamps and DRM's flip events.
#include "vpe/firmware/scan/scan_camera.h"

#include <cerrno>
#include <ctime>

namespace vpe::firmware {

namespace {

constexpr std::int64_t kNsPerSecond = 1'000'000'000;

}  // namespace

std::int64_t scanClockNs() {
    timespec now{};
    ::clock_gettime(CLOCK_MONOTONIC, &now);
    return static_cast<std::int64_t>(now.tv_sec) * kNsPerSecond + now.tv_nsec;
}

void sleepUntilNs(std::int64_t ns) {
    timespec until{};
    until.tv_sec = static_cast<time_t>(ns / kNsPerSecond);
    until.tv_nsec = static_cast<long>(ns % kNsPerSecond);
    // Absolute: a signal's interruption resumes towards the same instant.
    while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr) == EINTR) {
    }
}

}  // namespace vpe::firmware
