// SPDX-License-Identifier: MIT
// DebouncedButton: a push button's raw line level → presses. A level is accepted only once it
// has stayed unchanged for the debounce time, judged on the edges' own timestamps (so a replay
// decodes exactly as the live run did) and, when no further edge comes, on the loop's clock.
#pragma once

#include <cstdint>
#include <optional>

namespace vpe::firmware::knobs {

class DebouncedButton {
public:
    // `activeLow`: pressed pulls the line low (a switch to ground with a pull-up, KY-040's SW).
    // `level` is the line's level at `nowNs`, taken as already stable (a button held at start
    // does not fire).
    DebouncedButton(std::int64_t debounceNs, bool activeLow, bool level, std::int64_t nowNs);

    // The line changed to `level` at `timestampNs`. Returns the press it settles, if any: the
    // timestamp of the edge that began the accepted pressed level.
    std::optional<std::int64_t> onEdge(bool level, std::int64_t timestampNs);

    // Time alone settles a pending level once it has been stable for the debounce time.
    std::optional<std::int64_t> onTick(std::int64_t nowNs);

    // The debounced state.
    bool pressed() const { return accepted_ == pressedLevel_; }

private:
    std::optional<std::int64_t> settle(std::int64_t nowNs);

    std::int64_t debounceNs_;
    bool pressedLevel_;        // low when active-low
    bool accepted_;            // the debounced level
    bool raw_;                 // the line's last level
    std::int64_t rawSinceNs_;  // when raw_ began
};

}  // namespace vpe::firmware::knobs
