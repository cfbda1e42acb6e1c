// SPDX-License-Identifier: MIT
// OscDispatcher: one table of addresses, each with its argument count and its checks, in the
// order count → type → finiteness → range, so that a message is refused for its first fault.
#include "vpe/firmware/osc/osc_dispatcher.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>

namespace vpe::firmware {

namespace {

constexpr std::pair<double, double> kHardAzimuthDeg{-180.0, 180.0};
constexpr std::pair<double, double> kHardElevationDeg{-90.0, 90.0};

enum class Address : std::uint8_t {
    kAzimuth,
    kElevation,
    kDistance,
    kDirection,
    kPosition,
    kReset,
    kPreset,
    kNextPreset,
    kPreviousPreset,
    kStatus,
    kPing,
};

struct AddressEntry {
    std::string_view path;
    Address address;
};

constexpr std::array<AddressEntry, 11> kAddresses{{
    {"/vpe/light/azimuth", Address::kAzimuth},
    {"/vpe/light/elevation", Address::kElevation},
    {"/vpe/light/distance", Address::kDistance},
    {"/vpe/light/direction", Address::kDirection},
    {"/vpe/light/position", Address::kPosition},
    {"/vpe/light/reset", Address::kReset},
    {"/vpe/weights/preset", Address::kPreset},
    {"/vpe/weights/next", Address::kNextPreset},
    {"/vpe/weights/previous", Address::kPreviousPreset},
    {"/vpe/status", Address::kStatus},
    {"/vpe/ping", Address::kPing},
}};

std::string formatNumber(double value) {
    char buffer[32];
    const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
    return error == std::errc{} ? std::string(buffer, end) : std::string("?");
}

std::string formatRange(const std::pair<double, double>& range) {
    return "[" + formatNumber(range.first) + ", " + formatNumber(range.second) + "]";
}

std::pair<double, double> intersect(const std::pair<double, double>& range,
                                    const std::pair<double, double>& hard) {
    return {std::max(range.first, hard.first), std::min(range.second, hard.second)};
}

// i, h, f, d as a number; nullopt for anything else.
std::optional<double> numberOf(const OscArgument& argument) {
    if (const auto* i = std::get_if<std::int32_t>(&argument)) {
        return static_cast<double>(*i);
    }
    if (const auto* h = std::get_if<std::int64_t>(&argument)) {
        return static_cast<double>(*h);
    }
    if (const auto* f = std::get_if<float>(&argument)) {
        return static_cast<double>(*f);
    }
    if (const auto* d = std::get_if<double>(&argument)) {
        return *d;
    }
    return std::nullopt;
}

// How a message is refused, before it is counted: the dispatcher's checks return this.
struct Fault {
    OscRejection reason;
    std::string problem;
};

// The message's arguments as numbers, each finite: count, then types, then finiteness.
using Numbers = std::array<double, 3>;  // the most any address takes

std::variant<Numbers, Fault> numbersOf(std::span<const OscArgument> arguments,
                                       std::size_t expected) {
    if (arguments.size() != expected) {
        return Fault{OscRejection::kArgumentCount,
                     "expected " + std::to_string(expected) + " number" +
                         (expected == 1 ? "" : "s") + ", got " + std::to_string(arguments.size()) +
                         " argument" + (arguments.size() == 1 ? "" : "s")};
    }
    Numbers numbers{};
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::optional<double> number = numberOf(arguments[i]);
        if (!number) {
            return Fault{OscRejection::kArgumentType, "argument " + std::to_string(i + 1) +
                                                          " is '" + oscTypeTag(arguments[i]) +
                                                          "', expected a number (i, h, f, d)"};
        }
        numbers[i] = *number;
    }
    for (std::size_t i = 0; i < expected; ++i) {
        if (!std::isfinite(numbers[i])) {
            return Fault{OscRejection::kNotFinite,
                         "argument " + std::to_string(i + 1) + " is " + formatNumber(numbers[i])};
        }
    }
    return numbers;
}

std::optional<Fault> outside(double value, const std::pair<double, double>& range,
                             const char* what) {
    if (value >= range.first && value <= range.second) {
        return std::nullopt;
    }
    return Fault{OscRejection::kOutOfRange, std::string(what) + " " + formatNumber(value) +
                                                " is outside " + formatRange(range)};
}

// Distance: within the limits and strictly positive (a light at the centre has no direction).
std::optional<Fault> badDistance(double value, const std::pair<double, double>& range) {
    if (value > 0.0 && value >= range.first && value <= range.second) {
        return std::nullopt;
    }
    return Fault{OscRejection::kOutOfRange, "distance " + formatNumber(value) + " is outside " +
                                                formatRange(range) +
                                                (value <= 0.0 ? " (must be above 0)" : "")};
}

// A whole number from an i/h argument, or an f/d one without a fraction (TouchDesigner and
// QLab send floats by default).
std::variant<std::int64_t, Fault> wholeNumberOf(const OscArgument& argument, const char* what) {
    const std::optional<double> number = numberOf(argument);
    if (!number) {
        return Fault{OscRejection::kArgumentType,
                     std::string(what) + " is '" + oscTypeTag(argument) + "', expected a number"};
    }
    if (const auto* h = std::get_if<std::int64_t>(&argument)) {
        return *h;
    }
    if (!std::isfinite(*number)) {
        return Fault{OscRejection::kNotFinite, std::string(what) + " is " + formatNumber(*number)};
    }
    if (*number != std::floor(*number)) {
        return Fault{OscRejection::kArgumentType,
                     std::string(what) + " " + formatNumber(*number) + " is not a whole number"};
    }
    // Beyond ±2^62 nothing is in range; clamping keeps the conversion defined.
    return static_cast<std::int64_t>(std::clamp(*number, -4.6e18, 4.6e18));
}

}  // namespace

const char* oscRejectionName(OscRejection reason) {
    switch (reason) {
        case OscRejection::kUnknownAddress:
            return "unknown_address";
        case OscRejection::kArgumentCount:
            return "argument_count";
        case OscRejection::kArgumentType:
            return "argument_type";
        case OscRejection::kNotFinite:
            return "not_finite";
        case OscRejection::kOutOfRange:
            return "out_of_range";
        case OscRejection::kUnknownPreset:
            return "unknown_preset";
        case OscRejection::kMalformedPacket:
            return "malformed_packet";
        case OscRejection::kSourceNotAllowed:
            return "source_not_allowed";
    }
    return "unknown";
}

std::uint64_t OscCounters::rejectedTotal() const {
    return std::accumulate(rejected.begin(), rejected.end(), std::uint64_t{0});
}

std::map<std::string, std::uint64_t> OscCounters::rejectionsByName() const {
    std::map<std::string, std::uint64_t> named;
    for (std::size_t reason = 0; reason < kOscRejectionCount; ++reason) {
        if (rejected[reason] > 0) {
            named[std::string("osc.") + oscRejectionName(static_cast<OscRejection>(reason))] =
                rejected[reason];
        }
    }
    return named;
}

OscDispatcher::OscDispatcher(const OscLimits& limits, RateLimitedLog::Sink log)
    : log_(std::move(log)) {
    setLimits(limits);
}

void OscDispatcher::setLimits(const OscLimits& limits) {
    limits_ = limits;
    limits_.azimuthDeg = intersect(limits.azimuthDeg, kHardAzimuthDeg);
    limits_.elevationDeg = intersect(limits.elevationDeg, kHardElevationDeg);
    limits_.distanceM.first = std::max(limits.distanceM.first, 0.0);
}

void OscDispatcher::setPresetNames(std::vector<std::string> names) {
    presetNames_ = std::move(names);
}

OscOutcome OscDispatcher::reject(OscRejection reason, std::string problem,
                                 std::int64_t timestampNs) {
    ++counters_.rejected[static_cast<std::size_t>(reason)];
    OscOutcome outcome;
    outcome.rejection = reason;
    outcome.problem = std::move(problem);
    log_.write("osc: " + outcome.problem + " (" + oscRejectionName(reason) + ")", timestampNs);
    return outcome;
}

OscOutcome OscDispatcher::accept(OscOutcome outcome) {
    ++counters_.accepted;
    return outcome;
}

void OscDispatcher::rejectMalformed(const std::string& problem, std::int64_t timestampNs) {
    reject(OscRejection::kMalformedPacket, problem, timestampNs);
}

void OscDispatcher::rejectSource(const std::string& problem, std::int64_t timestampNs) {
    reject(OscRejection::kSourceNotAllowed, problem, timestampNs);
}

OscOutcome OscDispatcher::dispatch(std::string_view path, std::span<const OscArgument> arguments,
                                   std::int64_t timestampNs) {
    const auto entry = std::find_if(kAddresses.begin(), kAddresses.end(),
                                    [&](const AddressEntry& e) { return e.path == path; });
    if (entry == kAddresses.end()) {
        return reject(OscRejection::kUnknownAddress,
                      printableOscText(std::string(path)) + ": unknown address", timestampNs);
    }
    const auto refuse = [&](Fault fault) {
        const std::string tags = oscTypeTags(arguments);
        return reject(
            fault.reason,
            std::string(entry->path) + (tags.empty() ? "" : " " + tags) + ": " + fault.problem,
            timestampNs);
    };
    const auto event = [&](LightAction action) {
        OscOutcome outcome;
        outcome.event = InputEvent{InputSource::kOsc, timestampNs, std::move(action)};
        return accept(std::move(outcome));
    };
    const auto numbers = [&](std::size_t count) { return numbersOf(arguments, count); };

    switch (entry->address) {
        case Address::kAzimuth:
        case Address::kElevation:
        case Address::kDistance: {
            auto parsed = numbers(1);
            if (auto* fault = std::get_if<Fault>(&parsed)) {
                return refuse(std::move(*fault));
            }
            const double value = std::get<Numbers>(parsed)[0];
            AimLight aim;
            std::optional<Fault> fault;
            if (entry->address == Address::kAzimuth) {
                fault = outside(value, limits_.azimuthDeg, "azimuth");
                aim.azimuthDeg = value;
            } else if (entry->address == Address::kElevation) {
                fault = outside(value, limits_.elevationDeg, "elevation");
                aim.elevationDeg = value;
            } else {
                fault = badDistance(value, limits_.distanceM);
                aim.distanceM = value;
            }
            if (fault) {
                return refuse(std::move(*fault));
            }
            return event(aim);
        }
        case Address::kDirection: {
            auto parsed = numbers(2);
            if (auto* fault = std::get_if<Fault>(&parsed)) {
                return refuse(std::move(*fault));
            }
            const Numbers& values = std::get<Numbers>(parsed);
            std::optional<Fault> fault = outside(values[0], limits_.azimuthDeg, "azimuth");
            if (!fault) {
                fault = outside(values[1], limits_.elevationDeg, "elevation");
            }
            if (fault) {
                return refuse(std::move(*fault));
            }
            return event(AimLight{values[0], values[1], std::nullopt});
        }
        case Address::kPosition: {
            auto parsed = numbers(3);
            if (auto* fault = std::get_if<Fault>(&parsed)) {
                return refuse(std::move(*fault));
            }
            const Numbers& values = std::get<Numbers>(parsed);
            const std::pair<double, double> extent{-limits_.positionExtentM,
                                                   limits_.positionExtentM};
            constexpr const char* kAxes[] = {"x", "y", "z"};
            for (std::size_t i = 0; i < 3; ++i) {
                if (std::optional<Fault> fault = outside(values[i], extent, kAxes[i])) {
                    return refuse(std::move(*fault));
                }
            }
            return event(PlaceLight{{values[0], values[1], values[2]}});
        }
        case Address::kReset:
        case Address::kNextPreset:
        case Address::kPreviousPreset: {
            if (!arguments.empty()) {
                return refuse({OscRejection::kArgumentCount,
                               "expected no arguments, got " + std::to_string(arguments.size())});
            }
            if (entry->address == Address::kReset) {
                return event(ResetLight{});
            }
            return event(SelectPreset{entry->address == Address::kNextPreset ? 1 : -1, true});
        }
        case Address::kPreset: {
            if (arguments.size() != 1) {
                return refuse({OscRejection::kArgumentCount, "expected an index or a name, got " +
                                                                 std::to_string(arguments.size()) +
                                                                 " arguments"});
            }
            const int count = static_cast<int>(presetNames_.size());
            if (const auto* presetName = std::get_if<std::string>(&arguments[0])) {
                const auto found = std::find(presetNames_.begin(), presetNames_.end(), *presetName);
                if (found == presetNames_.end()) {
                    return refuse({OscRejection::kUnknownPreset,
                                   "no preset named \"" + printableOscText(*presetName) + "\" (" +
                                       std::to_string(count) + " presets)"});
                }
                return event(SelectPreset{static_cast<int>(found - presetNames_.begin()), false});
            }
            auto index = wholeNumberOf(arguments[0], "index");
            if (auto* fault = std::get_if<Fault>(&index)) {
                return refuse(std::move(*fault));
            }
            const std::int64_t value = std::get<std::int64_t>(index);
            if (value < 0 || value >= count) {
                return refuse({OscRejection::kOutOfRange, "index " + std::to_string(value) +
                                                              " is outside [0, " +
                                                              std::to_string(count - 1) + "] (" +
                                                              std::to_string(count) + " presets)"});
            }
            return event(SelectPreset{static_cast<int>(value), false});
        }
        case Address::kStatus:
        case Address::kPing: {
            OscReplyRequest request;
            request.query =
                entry->address == Address::kStatus ? OscQuery::kStatus : OscQuery::kPing;
            if (arguments.size() > 1) {
                return refuse({OscRejection::kArgumentCount,
                               "expected nothing or a reply port, got " +
                                   std::to_string(arguments.size()) + " arguments"});
            }
            if (arguments.size() == 1) {
                auto port = wholeNumberOf(arguments[0], "reply port");
                if (auto* fault = std::get_if<Fault>(&port)) {
                    return refuse(std::move(*fault));
                }
                const std::int64_t value = std::get<std::int64_t>(port);
                if (value < 1 || value > 65535) {
                    return refuse(
                        {OscRejection::kOutOfRange,
                         "reply port " + std::to_string(value) + " is outside [1, 65535]"});
                }
                request.port = static_cast<int>(value);
            }
            OscOutcome outcome;
            outcome.reply = request;
            return accept(std::move(outcome));
        }
    }
    return reject(OscRejection::kUnknownAddress, std::string(path) + ": unknown address",
                  timestampNs);
}

}  // namespace vpe::firmware
