// SPDX-License-Identifier: MIT
// ServiceWatchdog: the player's side of systemd's Type=notify + WatchdogSec= contract
// (boards/vpe-player.service). READY=1 once the first frame is out, WATCHDOG=1 from the frame
// loop at half the watchdog interval, so a hung GPU or a stuck loop gets the service
// restarted; STATUS= for `systemctl status`. Outside systemd (no NOTIFY_SOCKET) it does nothing.
#pragma once

#include <cstdint>
#include <string>

namespace vpe::firmware {

class ServiceWatchdog {
public:
    ServiceWatchdog();

    bool underSystemd() const { return notify_; }
    // The interval systemd expects pings within (0: no watchdog configured).
    std::int64_t intervalNs() const { return intervalNs_; }

    void ready(const std::string& status);
    // Called every frame; pings when half the interval has passed since the last ping.
    void frameDone(std::int64_t nowNs);
    void status(const std::string& text);
    void reloading();
    void reloaded(const std::string& status);
    void stopping();

private:
    bool notify_ = false;
    std::int64_t intervalNs_ = 0;
    std::int64_t lastPingNs_ = 0;
};

}  // namespace vpe::firmware
