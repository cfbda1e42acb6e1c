// SPDX-License-Identifier: MIT
// decodeMessageEnvelope: the checks every command message shares.
#include "message_envelope.h"

#include <utility>

namespace vpe::firmware::bus {

std::variant<MessageEnvelope, LightMessageRefusal> decodeMessageEnvelope(std::string_view payload,
                                                                         int format) {
    const auto malformed = [](std::string reason) {
        return LightMessageRefusal{LightMessageProblem::kMalformed, std::move(reason)};
    };
    if (payload.size() > kLightMessageMaxBytes) {
        return malformed(std::to_string(payload.size()) + " bytes, more than " +
                         std::to_string(kLightMessageMaxBytes));
    }
    MessageEnvelope out;
    out.body = nlohmann::json::parse(payload, nullptr, false);
    if (out.body.is_discarded() || !out.body.is_object()) {
        return malformed("not a JSON object");
    }
    const auto version = out.body.find("format");
    if (version == out.body.end() || !version->is_number_integer() ||
        version->get<std::int64_t>() != format) {
        return malformed("\"format\": expected " + std::to_string(format));
    }
    const auto node = out.body.find("node");
    if (node == out.body.end() || !node->is_string() || node->get<std::string>().empty() ||
        node->get<std::string>().size() > 64) {
        return malformed("\"node\": expected a name of 1-64 bytes");
    }
    out.node = node->get<std::string>();
    const auto time = out.body.find("time_us");
    if (time == out.body.end() || !time->is_number_integer()) {
        return malformed("\"time_us\": expected whole microseconds");
    }
    out.timeUs = time->get<std::int64_t>();
    if (out.timeUs < 1'000'000'000'000'000 || out.timeUs > 4'102'444'800'000'000) {
        return LightMessageRefusal{LightMessageProblem::kOutOfRange,
                                   "\"time_us\" " + std::to_string(out.timeUs) +
                                       " is not a wall-clock time in microseconds"};
    }
    return out;
}

}  // namespace vpe::firmware::bus
