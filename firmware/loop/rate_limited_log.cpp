// SPDX-License-Identifier: MIT
#include "vpe/firmware/loop/rate_limited_log.h"

#include <algorithm>
#include <iostream>

namespace vpe::firmware {

RateLimitedLog::RateLimitedLog(Sink sink, int burst, std::int64_t intervalNs)
    : sink_(std::move(sink)),
      burst_(std::max(burst, 1)),
      intervalNs_(std::max<std::int64_t>(intervalNs, 1)),
      tokens_(burst_) {}

bool RateLimitedLog::write(const std::string& line, std::int64_t nowNs) {
    if (!started_) {
        started_ = true;
        refilledNs_ = nowNs;
    }
    // A full bucket earns nothing: the clock restarts, so a quiet hour is not a credit of
    // hundreds of lines. Time going backwards (a replay's clock) earns nothing either.
    if (tokens_ >= burst_) {
        refilledNs_ = std::max(refilledNs_, nowNs);
    } else if (nowNs > refilledNs_) {
        const std::int64_t earned = (nowNs - refilledNs_) / intervalNs_;
        if (earned > 0) {
            tokens_ = static_cast<int>(std::min<std::int64_t>(burst_, tokens_ + earned));
            refilledNs_ = tokens_ >= burst_ ? nowNs : refilledNs_ + earned * intervalNs_;
        }
    }
    if (tokens_ == 0) {
        ++suppressed_;
        ++suppressedSinceWrite_;
        return false;
    }
    --tokens_;
    std::string out = line;
    if (suppressedSinceWrite_ > 0) {
        out += " (" + std::to_string(suppressedSinceWrite_) + " earlier not logged)";
        suppressedSinceWrite_ = 0;
    }
    if (sink_) {
        sink_(out);
    } else {
        std::cerr << out << '\n';
    }
    return true;
}

}  // namespace vpe::firmware
