// SPDX-License-Identifier: MIT
// RateLimitedLog: one line per event until a flood begins, then a trickle. A token bucket: a
// burst of lines is written at once, after which one more line is allowed per interval; the
// first line written after a quiet spell says how many were left out. Time is the caller's
// (the events' own timestamps), so a replay logs exactly what the live run logged.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace vpe::firmware {

class RateLimitedLog {
public:
    using Sink = std::function<void(const std::string& line)>;

    // An empty sink writes to stderr (the player's journal under systemd).
    explicit RateLimitedLog(Sink sink = {}, int burst = 5,
                            std::int64_t intervalNs = 10'000'000'000);

    // Writes `line` if the budget allows; returns whether it did.
    bool write(const std::string& line, std::int64_t nowNs);

    // Lines refused so far (over the log's life).
    std::uint64_t suppressed() const { return suppressed_; }

private:
    Sink sink_;
    int burst_;
    std::int64_t intervalNs_;
    int tokens_;
    bool started_ = false;
    std::int64_t refilledNs_ = 0;  // the time the last token was credited
    std::uint64_t suppressed_ = 0;
    std::uint64_t suppressedSinceWrite_ = 0;
};

}  // namespace vpe::firmware
