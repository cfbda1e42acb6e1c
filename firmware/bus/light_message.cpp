// SPDX-License-Identifier: MIT
// LightMessage: nlohmann-json (already the device's JSON reader, for replay files) both ways.
#include "vpe/firmware/bus/light_message.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

namespace vpe::firmware::bus {

namespace {

using nlohmann::json;

struct Refused {
    LightMessageRefusal refusal;
};

[[noreturn]] void malformed(const std::string& reason) {
    throw Refused{{LightMessageProblem::kMalformed, reason}};
}
[[noreturn]] void outOfRange(const std::string& reason) {
    throw Refused{{LightMessageProblem::kOutOfRange, reason}};
}

std::string text(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

const json& field(const json& object, const char* key, const std::string& where) {
    const auto found = object.find(key);
    if (found == object.end()) {
        malformed("\"" + where + key + "\" is missing");
    }
    return *found;
}

double number(const json& object, const char* key, const std::string& where) {
    const json& value = field(object, key, where);
    if (!value.is_number()) {
        malformed("\"" + where + key + "\": expected a number, got " + value.type_name());
    }
    const double result = value.get<double>();
    if (!std::isfinite(result)) {
        outOfRange("\"" + where + key + "\" is not finite");
    }
    return result;
}

std::int64_t microseconds(const json& value, const std::string& name) {
    if (!value.is_number_integer()) {
        malformed("\"" + name + "\": expected whole microseconds, got " + value.type_name());
    }
    const auto us = value.get<std::int64_t>();
    // Not before 2001, not beyond 2100: a time that is not the wall clock's.
    if (us < 1'000'000'000'000'000 || us > 4'102'444'800'000'000) {
        outOfRange("\"" + name + "\" " + std::to_string(us) +
                   " is not a time of the wall clock in microseconds");
    }
    return us;
}

std::string string(const json& object, const char* key, bool required) {
    const auto found = object.find(key);
    if (found == object.end()) {
        if (required) {
            malformed(std::string("\"") + key + "\" is missing");
        }
        return {};
    }
    if (!found->is_string()) {
        malformed(std::string("\"") + key + "\": expected a string, got " + found->type_name());
    }
    const auto value = found->get<std::string>();
    if (value.size() > 64) {
        malformed(std::string("\"") + key + "\": longer than 64 bytes");
    }
    return value;
}

void within(double value, const std::pair<double, double>& range, const std::string& name) {
    if (value < range.first || value > range.second) {
        outOfRange(name + " " + text(value) + " is outside [" + text(range.first) + ", " +
                   text(range.second) + "]");
    }
}

SphericalPosition position(const json& object, const std::string& where,
                           const LightLimits& limits) {
    SphericalPosition p;
    p.azimuthDeg = number(object, "azimuth", where);
    p.elevationDeg = number(object, "elevation", where);
    p.distanceM = number(object, "distance", where);
    const bool fullCircle = limits.azimuthDeg.second - limits.azimuthDeg.first >= 360.0;
    within(p.azimuthDeg, fullCircle ? std::pair{-180.0, 180.0} : limits.azimuthDeg,
           where + "azimuth");
    within(p.elevationDeg, limits.elevationDeg, where + "elevation");
    within(p.distanceM, limits.distanceM.value_or(std::pair{0.0, 1e6}), where + "distance");
    if (p.distanceM <= 0) {
        outOfRange(where + "distance " + text(p.distanceM) + " is not above 0");
    }
    return p;
}

LightMessage read(std::string_view payload, const LightLimits& limits) {
    if (payload.size() > kLightMessageMaxBytes) {
        malformed("a payload of " + std::to_string(payload.size()) +
                  " bytes (a light state is at most " + std::to_string(kLightMessageMaxBytes) +
                  ")");
    }
    const json root = json::parse(payload.begin(), payload.end(), nullptr, false);
    if (root.is_discarded()) {
        malformed("not JSON");
    }
    if (!root.is_object()) {
        malformed(std::string("expected a JSON object, got ") + root.type_name());
    }
    const json& format = field(root, "format", "");
    if (!format.is_number_integer() || format.get<std::int64_t>() != kLightMessageFormat) {
        malformed("format " + format.dump() + ": this node reads format " +
                  std::to_string(kLightMessageFormat));
    }
    LightMessage message;
    message.node = string(root, "node", true);
    if (message.node.empty()) {
        malformed("\"node\" is empty");
    }
    const json& seq = field(root, "seq", "");
    if (!seq.is_number_unsigned()) {
        malformed(std::string("\"seq\": expected a whole number from 0, got ") + seq.dump());
    }
    message.seq = seq.get<std::uint64_t>();
    message.timeUs = microseconds(field(root, "time_us", ""), "time_us");
    message.target = position(root, "", limits);
    const json& from = field(root, "from", "");
    if (!from.is_object()) {
        malformed(std::string("\"from\": expected an object, got ") + from.type_name());
    }
    message.from = position(from, "from.", limits);
    message.fromUs = microseconds(field(from, "time_us", "from."), "from.time_us");
    if (message.fromUs > message.timeUs) {
        outOfRange("from.time_us is after time_us (a move cannot start after the state was made)");
    }
    if (const auto drift = root.find("drift_us"); drift != root.end() && !drift->is_null()) {
        message.driftUs = microseconds(*drift, "drift_us");
        if (*message.driftUs < message.fromUs) {
            outOfRange("drift_us is before from.time_us (the drift starts after the move)");
        }
    }
    message.preset = string(root, "preset", false);
    message.source = string(root, "source", false);
    return message;
}

}  // namespace

std::string encodeLightMessage(const LightMessage& message) {
    // In the documented order (proto/BUS.md): what a person reading mosquitto_sub expects.
    using ordered = nlohmann::ordered_json;
    ordered root = {{"format", kLightMessageFormat},
                    {"node", message.node},
                    {"seq", message.seq},
                    {"time_us", message.timeUs},
                    {"azimuth", message.target.azimuthDeg},
                    {"elevation", message.target.elevationDeg},
                    {"distance", message.target.distanceM},
                    {"from",
                     {{"time_us", message.fromUs},
                      {"azimuth", message.from.azimuthDeg},
                      {"elevation", message.from.elevationDeg},
                      {"distance", message.from.distanceM}}},
                    {"drift_us", message.driftUs ? ordered(*message.driftUs) : ordered(nullptr)},
                    {"preset", message.preset},
                    {"source", message.source}};
    return root.dump();
}

std::variant<LightMessage, LightMessageRefusal> decodeLightMessage(std::string_view payload,
                                                                   const LightLimits& limits) {
    try {
        return read(payload, limits);
    } catch (const Refused& refused) {
        return refused.refusal;
    } catch (const nlohmann::json::exception& error) {
        // A value nlohmann cannot convert (a number beyond 64 bits): malformed, not a crash.
        return LightMessageRefusal{LightMessageProblem::kMalformed, error.what()};
    }
}

}  // namespace vpe::firmware::bus
