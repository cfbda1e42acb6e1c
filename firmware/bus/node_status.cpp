// SPDX-License-Identifier: MIT
// NodeStatus and BlackoutMessage as JSON (nlohmann-json, as the light's state).
#include "vpe/firmware/bus/node_status.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include <nlohmann/json.hpp>

#include "message_envelope.h"

namespace vpe::firmware::bus {

namespace {

using nlohmann::json;

// Three decimals: a status is read by people and drawn on a phone, not compared.
double rounded(double value) {
    return std::isfinite(value) ? std::round(value * 1000.0) / 1000.0 : 0.0;
}

json range(const std::pair<double, double>& limits) {
    return json::array({rounded(limits.first), rounded(limits.second)});
}

}  // namespace

std::string encodeNodeStatus(const NodeStatus& status) {
    json out = json::object();
    out["format"] = kNodeStatusFormat;
    out["node"] = status.node;
    out["role"] = status.role;
    out["time_us"] = status.timeUs;
    out["fps"] = rounded(status.fps);
    out["frame_p99_ms"] = rounded(status.frameP99Ms);
    out["skipped"] = status.skipped;
    out["soc_temp_c"] = status.socTemperatureC ? json(rounded(*status.socTemperatureC)) : json();
    out["bundle"] = status.bundle;
    out["bundle_checksum"] = status.bundleChecksum;
    out["input"] = status.activeInput;
    out["uptime_s"] = rounded(status.uptimeS);
    out["last_error"] = status.lastError;
    out["watchdog"] = status.watchdog;
    out["light"] = {{"azimuth", rounded(status.light.azimuthDeg)},
                    {"elevation", rounded(status.light.elevationDeg)},
                    {"distance", rounded(status.light.distanceM)}};
    json limits = {{"azimuth", range(status.limits.azimuthDeg)},
                   {"elevation", range(status.limits.elevationDeg)}};
    if (status.limits.distanceM) {
        limits["distance"] = range(*status.limits.distanceM);
    }
    out["limits"] = std::move(limits);
    out["presets"] = status.presets;
    out["preset"] = status.preset;
    out["blackout"] = status.blackout;
    // Replace invalid UTF-8 (a log line quoting the network) rather than throw.
    return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string encodeBlackoutMessage(const BlackoutMessage& message) {
    return json{{"format", kBlackoutMessageFormat},
                {"node", message.node},
                {"time_us", message.timeUs},
                {"on", message.on}}
        .dump(-1, ' ', false, json::error_handler_t::replace);
}

std::variant<BlackoutMessage, LightMessageRefusal> decodeBlackoutMessage(std::string_view payload) {
    auto envelope = decodeMessageEnvelope(payload, kBlackoutMessageFormat);
    if (auto* refusal = std::get_if<LightMessageRefusal>(&envelope)) {
        return std::move(*refusal);
    }
    auto& [message, node, timeUs] = std::get<MessageEnvelope>(envelope);
    BlackoutMessage out;
    out.node = std::move(node);
    out.timeUs = timeUs;
    const auto on = message.find("on");
    if (on == message.end() || !on->is_boolean()) {
        return LightMessageRefusal{LightMessageProblem::kMalformed,
                                   "\"on\": expected true or false"};
    }
    out.on = on->get<bool>();
    return out;
}

std::optional<double> readSocTemperature(const std::string& thermalRoot) {
    std::error_code error;
    for (int zone = 0; zone < 16; ++zone) {
        const std::filesystem::path path =
            std::filesystem::path(thermalRoot) / ("thermal_zone" + std::to_string(zone)) / "temp";
        if (!std::filesystem::exists(path, error)) {
            continue;
        }
        std::ifstream in(path);
        long milli = 0;
        if (in >> milli) {
            return static_cast<double>(milli) / 1000.0;
        }
    }
    return std::nullopt;
}

}  // namespace vpe::firmware::bus
