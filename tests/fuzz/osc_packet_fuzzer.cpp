// SPDX-License-Identifier: MIT
// libFuzzer target: arbitrary bytes as one OSC datagram, through the path a datagram takes in
// vpe-player (decodeOscPacket, then the OscDispatcher of proto/OSC.md). Whatever arrives, the
// packet decodes into messages or one line saying why not; every message is accepted or
// refused for one counted reason; an accepted event carries finite values inside the limits.
// Anything else aborts.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "vpe/firmware/osc/osc_dispatcher.h"
#include "vpe/firmware/osc/osc_packet.h"

namespace {

using namespace vpe::firmware;

void check(bool condition) {
    if (!condition) {
        std::abort();
    }
}

bool within(const std::pair<double, double>& range, double value) {
    return std::isfinite(value) && value >= range.first && value <= range.second;
}

// An accepted event holds only what the limits allow.
void checkEvent(const InputEvent& event, const OscLimits& limits, std::size_t presets) {
    check(event.source == InputSource::kOsc);
    if (const auto* aim = std::get_if<AimLight>(&event.action)) {
        check(!aim->azimuthDeg || within(limits.azimuthDeg, *aim->azimuthDeg));
        check(!aim->elevationDeg || within(limits.elevationDeg, *aim->elevationDeg));
        check(!aim->distanceM ||
              (within(limits.distanceM, *aim->distanceM) && *aim->distanceM > 0));
    } else if (const auto* place = std::get_if<PlaceLight>(&event.action)) {
        for (const double coordinate : place->position) {
            check(std::isfinite(coordinate) && std::fabs(coordinate) <= limits.positionExtentM);
        }
    } else if (const auto* preset = std::get_if<SelectPreset>(&event.action)) {
        check(preset->relative
                  ? (preset->value == 1 || preset->value == -1)
                  : (preset->value >= 0 && static_cast<std::size_t>(preset->value) < presets));
    } else {
        check(std::holds_alternative<ResetLight>(event.action));
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    OscLimits limits;
    limits.azimuthDeg = {-90.0, 90.0};
    limits.elevationDeg = {0.0, 80.0};
    limits.distanceM = {0.2, 3.0};
    std::uint64_t logged = 0;
    OscDispatcher dispatcher(limits, [&](const std::string& line) {
        check(!line.empty() && line.find('\n') == std::string::npos);
        ++logged;
    });
    const std::vector<std::string> presets{"stripes", "radial"};
    dispatcher.setPresetNames(presets);

    const OscPacket packet = decodeOscPacket(std::span<const std::uint8_t>(data, size));
    if (const auto* problem = std::get_if<std::string>(&packet)) {
        check(!problem->empty());
        dispatcher.rejectMalformed(*problem, 0);
        check(dispatcher.counters().rejectedFor(OscRejection::kMalformedPacket) == 1);
        check(logged == 1);
        return 0;
    }
    const auto& messages = std::get<std::vector<OscMessage>>(packet);
    std::uint64_t seen = 0;
    for (const OscMessage& message : messages) {
        const OscOutcome outcome = dispatcher.dispatch(message.path, message.arguments, 1);
        ++seen;
        if (outcome.accepted()) {
            check(outcome.event.has_value() != outcome.reply.has_value());
            if (outcome.event) {
                checkEvent(*outcome.event, dispatcher.limits(), presets.size());
            }
        } else {
            check(!outcome.event && !outcome.reply && !outcome.problem.empty());
        }
        const OscCounters& counters = dispatcher.counters();
        check(counters.accepted + counters.rejectedTotal() == seen);
    }
    return 0;
}
