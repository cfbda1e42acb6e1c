// SPDX-License-Identifier: MIT
// Bouncy turns: a generated encoder script for the bounce tests. A random walk of intended
// detents (the direction changes at random, and some turns stop half way and come back), where
// every intended transition on a contact is preceded by a random burst of chatter on that same
// contact: it toggles to the new level and back an even number of times, so the contact ends
// where it began before the real edge. The checker runs a decoder over it and counts lost and
// phantom detents against the intended ones.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

namespace vpe::firmware::knobs::testing {

enum class Contact : std::uint8_t { kA, kB };

struct ScriptEdge {
    Contact contact = Contact::kA;
    bool level = true;  // the contact's level after the edge
    std::int64_t timestampNs = 0;
    bool chatter = false;  // part of a burst, not an intended transition
};

struct BouncyTurnsOptions {
    std::uint64_t seed = 1;
    int stepsPerDetent = 4;
    std::int64_t transitions = 1'000'000;  // intended transitions (chatter comes on top)
    int maxChatterPairs = 4;               // a burst is 0 … max back-and-forth pairs
    // Drop this intended transition (0-based): the decoder never sees it, as when the kernel
    // loses an event. For the test that shows the check can fail.
    std::optional<std::int64_t> dropTransition;
};

struct BounceTally {
    std::int64_t transitions = 0;         // intended transitions made
    std::int64_t chatterEdges = 0;        // edges of the bursts
    std::int64_t abortedTurns = 0;        // turns that went part way and came back
    std::int64_t intended = 0;            // intended detents
    std::int64_t decoded = 0;             // detents the decoder reported
    std::int64_t lost = 0;                // intended detents without a matching report
    std::int64_t phantom = 0;             // reports without an intended detent
    std::int64_t positionMismatches = 0;  // detent boundaries where the sums differ
};

// A decoder under test: sees each edge with both contacts' levels after it; returns the detent
// it reports there (+1, −1) or 0. The contacts start high (a KY-040 at rest).
using DecodeFn = std::function<int(const ScriptEdge& edge, bool levelA, bool levelB)>;

// Generates the script and checks `decode` on it. The intended detents are compared per
// interval between detent boundaries (the last intended edge of each detent): one report of the
// intended direction is a match, a missing one is lost, any other report is a phantom; and the
// running sum of reports must equal the intended position at every boundary.
BounceTally checkBouncyTurns(const BouncyTurnsOptions& options, const DecodeFn& decode);

}  // namespace vpe::firmware::knobs::testing
