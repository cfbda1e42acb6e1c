// SPDX-License-Identifier: MIT
// InstallCommand and InstallProgress as JSON (nlohmann-json, as the light's state).
#include "vpe/firmware/bus/install_message.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include <nlohmann/json.hpp>

#include "message_envelope.h"

namespace vpe::firmware::bus {

namespace {

using nlohmann::json;

constexpr std::int64_t kMaxAheadUs = 2'000'000;

double rounded(double value) {
    return std::isfinite(value) ? std::round(value * 1000.0) / 1000.0 : 0.0;
}

}  // namespace

const char* installActionName(InstallAction action) {
    return action == InstallAction::kRadiometry ? "radiometry" : "scan";
}

const char* installStateName(InstallState state) {
    switch (state) {
        case InstallState::kRunning:
            return "running";
        case InstallState::kDone:
            return "done";
        case InstallState::kFailed:
            return "failed";
    }
    return "";
}

std::string encodeInstallCommand(const InstallCommand& command) {
    return nlohmann::ordered_json{{"format", kInstallMessageFormat},
                                  {"node", command.node},
                                  {"time_us", command.timeUs},
                                  {"action", installActionName(command.action)}}
        .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::variant<InstallCommand, LightMessageRefusal> decodeInstallCommand(std::string_view payload,
                                                                       std::int64_t nowUs,
                                                                       std::int64_t maxAgeUs) {
    const auto malformed = [](std::string reason) {
        return LightMessageRefusal{LightMessageProblem::kMalformed, std::move(reason)};
    };
    const auto outOfRange = [](std::string reason) {
        return LightMessageRefusal{LightMessageProblem::kOutOfRange, std::move(reason)};
    };
    auto envelope = decodeMessageEnvelope(payload, kInstallMessageFormat);
    if (auto* refusal = std::get_if<LightMessageRefusal>(&envelope)) {
        return std::move(*refusal);
    }
    auto& [message, node, timeUs] = std::get<MessageEnvelope>(envelope);
    InstallCommand out;
    out.node = std::move(node);
    out.timeUs = timeUs;
    const auto action = message.find("action");
    if (action == message.end() || !action->is_string()) {
        return malformed("\"action\": expected \"scan\" or \"radiometry\"");
    }
    const std::string name = action->get<std::string>();
    if (name == "scan") {
        out.action = InstallAction::kScan;
    } else if (name == "radiometry") {
        out.action = InstallAction::kRadiometry;
    } else {
        return outOfRange("\"action\" \"" + name.substr(0, 32) +
                          "\" is not \"scan\" or \"radiometry\"");
    }
    if (out.timeUs > nowUs + kMaxAheadUs || out.timeUs < nowUs - maxAgeUs) {
        char age[32];
        std::snprintf(age, sizeof age, "%.1f", static_cast<double>(nowUs - out.timeUs) * 1e-6);
        return outOfRange(
            std::string("made ") + age + " s before this node's clock (a command older than " +
            std::to_string(maxAgeUs / 1'000'000) + " s, or from the future, runs nothing)");
    }
    return out;
}

std::string encodeInstallProgress(const InstallProgress& progress) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    out["format"] = kInstallMessageFormat;
    out["node"] = progress.node;
    out["time_us"] = progress.timeUs;
    out["action"] = installActionName(progress.action);
    out["requested_by"] = progress.requestedBy;
    out["state"] = installStateName(progress.state);
    out["step"] = progress.step;
    out["frames_done"] = progress.framesDone;
    out["frames_total"] = progress.framesTotal;
    out["elapsed_s"] = rounded(progress.elapsedS);
    out["out"] = progress.out;
    out["result"] = progress.result;
    out["error"] = progress.error;
    out["lit_fraction"] = progress.litFraction
                              ? nlohmann::ordered_json(rounded(*progress.litFraction))
                              : nlohmann::ordered_json();
    out["decodable_fraction"] = progress.decodableFraction
                                    ? nlohmann::ordered_json(rounded(*progress.decodableFraction))
                                    : nlohmann::ordered_json();
    return out.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace vpe::firmware::bus
