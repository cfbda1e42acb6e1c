// SPDX-License-Identifier: MIT
// NodeStatus and BlackoutMessage: the control page's side of the show's bus (proto/BUS.md,
// "Node status" and "Blackout"; firmware/control_page/). Every node publishes a retained status
// once a second on vpe/<show>/status/<client id>, what a technician or the gallery staff check
// from a phone; the page's blackout switch is one retained message on vpe/<show>/blackout that
// every node follows.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vpe/firmware/bus/light_message.h"

namespace vpe::firmware::bus {

inline constexpr int kNodeStatusFormat = 1;
inline constexpr int kBlackoutMessageFormat = 1;

struct NodeStatus {
    std::string node;  // the client id
    std::string role;  // "player", "controller"
    std::int64_t timeUs = 0;
    // The last second's frames: drawn per second, the 99th percentile of their draw times, and
    // ticks with nothing new to draw.
    double fps = 0;
    double frameP99Ms = 0;
    std::uint64_t skipped = 0;
    std::optional<double> socTemperatureC;  // /sys/class/thermal; empty where absent
    std::string bundle;                     // the bundle file's name
    std::string bundleChecksum;             // its header's CRC-32, "0x1a2b3c4d"
    std::string activeInput;                // "knobs", "camera", "osc", "bus", "idle", ...
    double uptimeS = 0;
    std::string lastError;  // the newest error line, empty: none
    std::string watchdog;   // "systemd 10 s", "systemd, no watchdog", "off (not under systemd)"
    SphericalPosition light;
    LightLimits limits;  // distance resolved
    std::vector<std::string> presets;
    std::string preset;
    bool blackout = false;
};

std::string encodeNodeStatus(const NodeStatus& status);

struct BlackoutMessage {
    std::string node;  // who switched it (the page's client id)
    std::int64_t timeUs = 0;
    bool on = false;
};

std::string encodeBlackoutMessage(const BlackoutMessage& message);
// Strict, as decodeLightMessage: a refusal names the key and what was wrong.
std::variant<BlackoutMessage, LightMessageRefusal> decodeBlackoutMessage(std::string_view payload);

// The SoC's temperature in °C from the first /sys/class/thermal/thermal_zone*/temp that reads
// (millidegrees), empty where there is none (a container, a desktop without zones).
std::optional<double> readSocTemperature(const std::string& thermalRoot = "/sys/class/thermal");

}  // namespace vpe::firmware::bus
