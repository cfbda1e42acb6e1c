// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/service_watchdog.h"

#include <cstdlib>

#include <systemd/sd-daemon.h>

namespace vpe::firmware {

ServiceWatchdog::ServiceWatchdog() {
    const char* socket = std::getenv("NOTIFY_SOCKET");
    notify_ = socket != nullptr && *socket != '\0';
    std::uint64_t usec = 0;
    // > 0 only when WatchdogSec= is set and the watchdog is meant for this process.
    if (notify_ && sd_watchdog_enabled(0, &usec) > 0) {
        intervalNs_ = static_cast<std::int64_t>(usec) * 1000;
    }
}

void ServiceWatchdog::ready(const std::string& text) {
    if (notify_) {
        sd_notify(0, ("READY=1\nSTATUS=" + text).c_str());
    }
}

void ServiceWatchdog::frameDone(std::int64_t nowNs) {
    if (intervalNs_ > 0 && nowNs - lastPingNs_ >= intervalNs_ / 2) {
        sd_notify(0, "WATCHDOG=1");
        lastPingNs_ = nowNs;
    }
}

void ServiceWatchdog::status(const std::string& text) {
    if (notify_) {
        sd_notify(0, ("STATUS=" + text).c_str());
    }
}

void ServiceWatchdog::reloading() {
    if (notify_) {
        sd_notify(0, "RELOADING=1");
    }
}

void ServiceWatchdog::reloaded(const std::string& text) {
    if (notify_) {
        sd_notify(0, ("READY=1\nSTATUS=" + text).c_str());
    }
}

void ServiceWatchdog::stopping() {
    if (notify_) {
        sd_notify(0, "STOPPING=1");
    }
}

}  // namespace vpe::firmware
