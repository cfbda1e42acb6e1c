// SPDX-License-Identifier: MIT
// QuadratureDecoder: the 16-entry transition table and the detent rule.
#include "vpe/firmware/knobs/quadrature_decoder.h"

#include <array>

namespace vpe::firmware::knobs {

namespace {

// A skipped state: both contacts changed between two updates, so an edge was missed and the
// direction is unknown.
constexpr int kSkipped = 2;

// The transition table, indexed by (previous state << 2) | current state, a state being
// (A << 1) | B. Clockwise, a KY-040 walks 11 → 01 → 00 → 10 → 11 (A leads B by a quarter
// cycle), each step +1; counter-clockwise the reverse, each −1.
//
//                  current:  00   01   10   11
//      previous 00           0   −1   +1    S
//      previous 01          +1    0    S   −1
//      previous 10          −1    S    0   +1
//      previous 11           S   +1   −1    0
//
// 0: no change (an edge that did not change the level, e.g. a repeated event). S: skipped
// state (both contacts changed: an edge was lost); counted as two steps in the direction of
// the last step, which keeps the count in phase with the contacts (a lost edge at speed is most
// likely one more step the same way).
// clang-format off
constexpr std::array<int, 16> kTransition = {
    0,  -1, +1, kSkipped,  // from 00
    +1, 0,  kSkipped, -1,  // from 01
    -1, kSkipped, 0,  +1,  // from 10
    kSkipped, +1, -1, 0,   // from 11
};
// clang-format on

// The detent rule (what makes it a "full-step" decoder): transitions are summed into a position,
// and a detent is reported only when the position reaches a multiple of the steps per detent
// other than the one last reported. Bounce is back-and-forth on one contact, i.e. ±1 around the
// current position: crossing into a detent position and back reports that detent once (on the
// first arrival) and never its reverse, because returning to the position of the last reported
// detent reports nothing. Going on to the next detent needs all `stepsPerDetent` transitions,
// which is exactly the full 4-transition cycle of the classic full-step state machine when
// stepsPerDetent = 4. At 1 step per detent every transition is a detent, so chatter there nets
// to zero but does show as +1/−1 pairs: bounce immunity needs 2 or 4 steps per detent.
std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

std::int64_t ceilDiv(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && a > 0) ? q + 1 : q;
}

unsigned stateOf(bool levelA, bool levelB) {
    return (levelA ? 2U : 0U) | (levelB ? 1U : 0U);
}

}  // namespace

QuadratureDecoder::QuadratureDecoder(int stepsPerDetent, bool levelA, bool levelB)
    : stepsPerDetent_(stepsPerDetent == 1 || stepsPerDetent == 2 ? stepsPerDetent : 4),
      state_(stateOf(levelA, levelB)) {}

std::optional<Detent> QuadratureDecoder::update(bool levelA, bool levelB,
                                                std::int64_t timestampNs) {
    const unsigned next = stateOf(levelA, levelB);
    const int step = kTransition[(state_ << 2) | next];
    state_ = next;
    if (step == 0) {
        return std::nullopt;
    }
    if (step == kSkipped) {
        position_ += 2 * lastDirection_;
    } else {
        position_ += step;
        lastDirection_ = step;
    }

    // The detent the position is in, seen from the last one reported: rounding towards it
    // gives the hysteresis (positions strictly between two detents belong to the last one).
    const std::int64_t reported = detent_ * stepsPerDetent_;
    const std::int64_t reached = position_ >= reported ? floorDiv(position_, stepsPerDetent_)
                                                       : ceilDiv(position_, stepsPerDetent_);
    if (reached == detent_) {
        return std::nullopt;
    }
    // A skipped state at 1 step per detent can cross two detents; one is reported.
    const int direction = reached > detent_ ? 1 : -1;
    detent_ = reached;
    return Detent{direction, timestampNs};
}

}  // namespace vpe::firmware::knobs
