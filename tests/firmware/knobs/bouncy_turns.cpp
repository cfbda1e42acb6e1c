// SPDX-License-Identifier: MIT
// Bouncy turns: the generator and the lost/phantom check.
#include "bouncy_turns.h"

#include <array>
#include <random>

namespace vpe::firmware::knobs::testing {

namespace {

// The clockwise cycle of a KY-040, (A, B): 11 → 01 → 00 → 10 → 11.
constexpr std::array<bool, 4> kCycleA = {true, false, false, true};
constexpr std::array<bool, 4> kCycleB = {true, true, false, false};

class Walk {
public:
    Walk(const BouncyTurnsOptions& options, const DecodeFn& decode)
        : options_(options), decode_(decode), rng_(options.seed) {}

    BounceTally run() {
        const int steps = options_.stepsPerDetent;
        std::bernoulli_distribution reverse(0.3);
        std::bernoulli_distribution abort(0.1);
        std::uniform_int_distribution<int> partial(1, steps > 1 ? steps - 1 : 1);
        int direction = 1;
        while (tally_.transitions < options_.transitions) {
            if (reverse(rng_)) {
                direction = -direction;
            }
            if (steps > 1 && abort(rng_)) {
                // A turn stopped short of the next detent: back to the same one.
                const int part = partial(rng_);
                for (int i = 0; i < part; ++i) {
                    transition(direction);
                }
                for (int i = 0; i < part; ++i) {
                    transition(-direction);
                }
                ++tally_.abortedTurns;
            }
            for (int i = 0; i < steps; ++i) {
                transition(direction);
            }
            closeDetent(direction);
        }
        return tally_;
    }

private:
    void feed(const ScriptEdge& edge) {
        (edge.contact == Contact::kA ? levelA_ : levelB_) = edge.level;
        const int reported = decode_(edge, levelA_, levelB_);
        if (reported > 0) {
            ++plus_;
            ++decodedPosition_;
        } else if (reported < 0) {
            ++minus_;
            --decodedPosition_;
        }
        tally_.decoded += reported != 0 ? 1 : 0;
    }

    void transition(int direction) {
        const int next = (phase_ + direction + 4) % 4;
        const Contact contact = kCycleA[next] != kCycleA[phase_] ? Contact::kA : Contact::kB;
        const bool level = contact == Contact::kA ? kCycleA[next] : kCycleB[next];
        std::uniform_int_distribution<int> pairs(0, options_.maxChatterPairs);
        std::uniform_int_distribution<std::int64_t> chatterGap(2'000, 200'000);    // 2–200 µs
        std::uniform_int_distribution<std::int64_t> realGap(200'000, 20'000'000);  // 0.2–20 ms
        time_ += realGap(rng_);
        for (int burst = pairs(rng_); burst > 0; --burst) {
            time_ += chatterGap(rng_);
            feed(ScriptEdge{contact, level, time_, true});
            time_ += chatterGap(rng_);
            feed(ScriptEdge{contact, !level, time_, true});
            tally_.chatterEdges += 2;
        }
        time_ += chatterGap(rng_);
        if (options_.dropTransition != tally_.transitions) {
            feed(ScriptEdge{contact, level, time_, false});
        }
        ++tally_.transitions;
        phase_ = next;
    }

    void closeDetent(int direction) {
        intendedPosition_ += direction;
        ++tally_.intended;
        const bool matched = direction > 0 ? plus_ > 0 : minus_ > 0;
        tally_.lost += matched ? 0 : 1;
        tally_.phantom += plus_ + minus_ - (matched ? 1 : 0);
        tally_.positionMismatches += decodedPosition_ != intendedPosition_ ? 1 : 0;
        plus_ = 0;
        minus_ = 0;
    }

    const BouncyTurnsOptions& options_;
    const DecodeFn& decode_;
    std::mt19937_64 rng_;
    BounceTally tally_;
    int phase_ = 0;
    bool levelA_ = true;
    bool levelB_ = true;
    std::int64_t time_ = 1'000'000'000;
    std::int64_t intendedPosition_ = 0;
    std::int64_t decodedPosition_ = 0;
    std::int64_t plus_ = 0;
    std::int64_t minus_ = 0;
};

}  // namespace

BounceTally checkBouncyTurns(const BouncyTurnsOptions& options, const DecodeFn& decode) {
    return Walk(options, decode).run();
}

}  // namespace vpe::firmware::knobs::testing
