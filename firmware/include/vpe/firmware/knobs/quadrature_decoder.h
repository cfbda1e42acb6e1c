// SPDX-License-Identifier: MIT
// QuadratureDecoder: a rotary encoder's two contacts (A, B) → detents, immune to contact bounce.
// Fed the levels of A and B after every edge; a detent is reported only when the shaft has
// walked every transition from one detent position to the next, so chatter on one contact
// (back and forth across the same transition) never adds or loses a detent.
#pragma once

#include <cstdint>
#include <optional>

namespace vpe::firmware::knobs {

// One click of the knob: +1 clockwise (A leads: A falls while B is high, KY-040 wiring), −1
// counter-clockwise; the timestamp of the edge that completed it.
struct Detent {
    int direction = 0;
    std::int64_t timestampNs = 0;
};

class QuadratureDecoder {
public:
    // `stepsPerDetent`: quadrature transitions between two rest positions: 4 (one full cycle,
    // KY-040 and most panel encoders), 2 (half cycle) or 1 (every transition). Any other value
    // is treated as 4. The initial levels are a rest position (a mechanical detent holds the
    // shaft there: A = B = high for a KY-040 with pull-ups); detents are counted from it.
    explicit QuadratureDecoder(int stepsPerDetent = 4, bool levelA = true, bool levelB = true);

    // The levels after an edge at `timestampNs`. Returns a detent when this edge completes one.
    std::optional<Detent> update(bool levelA, bool levelB, std::int64_t timestampNs);

    int stepsPerDetent() const { return stepsPerDetent_; }
    // Quadrature transitions counted so far (+ clockwise), and the detent the decoder is at: the
    // sum of the detents reported (unless a skipped state at 1 step per detent crossed two).
    std::int64_t transitions() const { return position_; }
    std::int64_t detents() const { return detent_; }

private:
    int stepsPerDetent_;
    unsigned state_;             // (A << 1) | B
    std::int64_t position_ = 0;  // transitions from the initial rest position, + clockwise
    std::int64_t detent_ = 0;    // the detent last reported (position_ was detent_ × steps)
    int lastDirection_ = 1;      // of the last single transition, to resolve a skipped state
};

}  // namespace vpe::firmware::knobs
