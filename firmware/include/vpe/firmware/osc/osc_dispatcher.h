// SPDX-License-Identifier: MIT
// OscDispatcher: the address space of proto/OSC.md, without sockets. It turns one message into
// an InputEvent (source kOsc), a query to answer (/vpe/status, /vpe/ping), or a rejection with
// its reason; it counts both and logs the first rejections one line each, then a trickle, so
// a flood cannot fill the journal. The OscServer feeds it from the network, a replay from a
// file: the same messages give the same events.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/loop/rate_limited_log.h"
#include "vpe/firmware/osc/osc_message.h"

namespace vpe::firmware {

// What OSC may ask for: the light rig's limits (the board's [light] section). Each range is
// intersected with the hard range of proto/OSC.md: azimuth [-180, 180]°, elevation [-90, 90]°,
// distance above 0 m. The defaults are the hard ranges.
struct OscLimits {
    std::pair<double, double> azimuthDeg{-180.0, 180.0};
    std::pair<double, double> elevationDeg{-90.0, 90.0};
    std::pair<double, double> distanceM{0.0, std::numeric_limits<double>::infinity()};
    // /vpe/light/position: each coordinate within ±this many metres of the object frame's
    // origin. The rig then clamps the position's sphere coordinates to its limits.
    double positionExtentM = 100.0;
};

// Why a message was refused; each reason has its own counter.
enum class OscRejection : std::uint8_t {
    kUnknownAddress,    // not an address of proto/OSC.md (patterns are not expanded)
    kArgumentCount,     // too many or too few arguments
    kArgumentType,      // a string where a number is expected, a blob, a fractional index, …
    kNotFinite,         // NaN or ±infinity
    kOutOfRange,        // outside OscLimits, or a preset index beyond the bundle's presets
    kUnknownPreset,     // a preset name the bundle does not have
    kMalformedPacket,   // the datagram is not OSC (counted by the server, see rejectMalformed)
    kSourceNotAllowed,  // a datagram from a sender not in [osc] allow (counted by the server)
};
inline constexpr std::size_t kOscRejectionCount = 8;

// "unknown_address", "argument_count", … (logs, tests, the README's table).
const char* oscRejectionName(OscRejection reason);

enum class OscQuery : std::uint8_t { kStatus, kPing };

// An accepted query: reply to the sender's address, or to the sender's host at `port` when
// the query named one (senders such as Max send from one port and listen on another).
struct OscReplyRequest {
    OscQuery query = OscQuery::kPing;
    std::optional<int> port;
};

// One message's fate: an event or a query when accepted, else the reason and one line.
struct OscOutcome {
    std::optional<InputEvent> event;
    std::optional<OscReplyRequest> reply;
    std::optional<OscRejection> rejection;
    std::string problem;  // "/vpe/light/azimuth: 270 is outside [-180, 180]"

    bool accepted() const { return !rejection.has_value(); }
};

struct OscCounters {
    std::uint64_t accepted = 0;
    std::array<std::uint64_t, kOscRejectionCount> rejected{};

    std::uint64_t rejectedFor(OscRejection reason) const {
        return rejected[static_cast<std::size_t>(reason)];
    }
    std::uint64_t rejectedTotal() const;
    // The non-zero rejection counters as "osc.<reason>" → count (InputDevice::refusals).
    std::map<std::string, std::uint64_t> rejectionsByName() const;
};

class OscDispatcher {
public:
    // `log` receives the rejection lines ("osc: /vpe/light/azimuth: 270 is outside [-180,
    // 180] (out_of_range)"); empty: stderr. At most 5 at once, then one per 10 s.
    explicit OscDispatcher(const OscLimits& limits = {}, RateLimitedLog::Sink log = {});

    void setLimits(const OscLimits& limits);
    // The bundle's weight presets, in index order: /vpe/weights/preset checks indices against
    // them and looks names up in them. Until told, every preset selection is refused.
    void setPresetNames(std::vector<std::string> names);

    // `timestampNs`: CLOCK_MONOTONIC arrival time, stamped on the event and used by the log's
    // rate limit. Type tags come from the arguments' alternatives (oscTypeTag).
    OscOutcome dispatch(std::string_view path, std::span<const OscArgument> arguments,
                        std::int64_t timestampNs);

    // A datagram that did not decode (decodeOscPacket's line): counted as kMalformedPacket
    // and logged like any rejection.
    void rejectMalformed(const std::string& problem, std::int64_t timestampNs);
    // A datagram from a sender the [osc] allow list leaves out: counted as kSourceNotAllowed
    // and logged like any rejection, never decoded.
    void rejectSource(const std::string& problem, std::int64_t timestampNs);

    const OscCounters& counters() const { return counters_; }
    // The effective limits (intersected with the hard ranges).
    const OscLimits& limits() const { return limits_; }
    const std::vector<std::string>& presetNames() const { return presetNames_; }
    // Rejection lines the rate limit left out.
    std::uint64_t unloggedRejections() const { return log_.suppressed(); }

private:
    OscOutcome reject(OscRejection reason, std::string problem, std::int64_t timestampNs);
    OscOutcome accept(OscOutcome outcome);

    OscLimits limits_;
    std::vector<std::string> presetNames_;
    OscCounters counters_;
    RateLimitedLog log_;
};

}  // namespace vpe::firmware
