// SPDX-License-Identifier: MIT
// DebouncedButton: accept a level after it has been stable for the debounce time.
#include "vpe/firmware/knobs/debounced_button.h"

#include <algorithm>

namespace vpe::firmware::knobs {

DebouncedButton::DebouncedButton(std::int64_t debounceNs, bool activeLow, bool level,
                                 std::int64_t nowNs)
    : debounceNs_(std::max<std::int64_t>(debounceNs, 0)),
      pressedLevel_(!activeLow),
      accepted_(level),
      raw_(level),
      rawSinceNs_(nowNs) {}

std::optional<std::int64_t> DebouncedButton::settle(std::int64_t nowNs) {
    if (raw_ == accepted_ || nowNs - rawSinceNs_ < debounceNs_) {
        return std::nullopt;
    }
    accepted_ = raw_;
    if (accepted_ == pressedLevel_) {
        return rawSinceNs_;
    }
    return std::nullopt;
}

std::optional<std::int64_t> DebouncedButton::onEdge(bool level, std::int64_t timestampNs) {
    // The level before this edge may have been stable long enough already (no tick came
    // between). Presses and releases alternate, so at most one of the two settles is a press.
    std::optional<std::int64_t> press = settle(timestampNs);
    if (level != raw_) {
        raw_ = level;
        // An edge stamped before the previous one (lines merged across reads) restarts the
        // wait from the later time, never earlier.
        rawSinceNs_ = std::max(timestampNs, rawSinceNs_);
    }
    if (std::optional<std::int64_t> settled = settle(timestampNs)) {
        press = settled;
    }
    return press;
}

std::optional<std::int64_t> DebouncedButton::onTick(std::int64_t nowNs) {
    return settle(nowNs);
}

}  // namespace vpe::firmware::knobs
