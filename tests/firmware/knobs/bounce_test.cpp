// SPDX-License-Identifier: MIT
// Contact bounce: 1,000,000 intended transitions, each preceded by random chatter on its own
// contact, through the QuadratureDecoder (and through the KnobEdgeSink, the path a replay
// drives): no detent lost, none invented. And the check itself catches a naive decoder and a
// single dropped edge.
#include <chrono>
#include <cstdio>
#include <variant>

#include <gtest/gtest.h>

#include "vpe/firmware/knobs/knob_edge_sink.h"
#include "vpe/firmware/knobs/quadrature_decoder.h"

#include "bouncy_turns.h"

namespace vpe::firmware::knobs {
namespace {

using testing::BounceTally;
using testing::BouncyTurnsOptions;
using testing::checkBouncyTurns;
using testing::Contact;
using testing::ScriptEdge;

testing::DecodeFn decoderUnderTest(QuadratureDecoder& decoder) {
    return [&decoder](const ScriptEdge& edge, bool a, bool b) {
        const std::optional<Detent> detent = decoder.update(a, b, edge.timestampNs);
        if (detent && detent->timestampNs != edge.timestampNs) {
            ADD_FAILURE() << "a detent stamped " << detent->timestampNs << " at an edge stamped "
                          << edge.timestampNs;
        }
        return detent ? detent->direction : 0;
    };
}

void print(const char* what, const BounceTally& tally, double ms) {
    std::printf(
        "[ bounce   ] %s: %lld transitions + %lld chatter edges, %lld aborted turns; "
        "%lld intended detents, %lld decoded, lost %lld, phantom %lld, position mismatches "
        "%lld; %.0f ms\n",
        what, static_cast<long long>(tally.transitions), static_cast<long long>(tally.chatterEdges),
        static_cast<long long>(tally.abortedTurns), static_cast<long long>(tally.intended),
        static_cast<long long>(tally.decoded), static_cast<long long>(tally.lost),
        static_cast<long long>(tally.phantom), static_cast<long long>(tally.positionMismatches),
        ms);
}

// Seed, quadrature steps per detent and intended transitions; the chatter as by default.
BouncyTurnsOptions bouncyTurns(std::uint64_t seed, int stepsPerDetent, std::int64_t transitions) {
    BouncyTurnsOptions options;
    options.seed = seed;
    options.stepsPerDetent = stepsPerDetent;
    options.transitions = transitions;
    return options;
}

BounceTally runTimed(const char* what, const BouncyTurnsOptions& options,
                     const testing::DecodeFn& decode) {
    const auto start = std::chrono::steady_clock::now();
    const BounceTally tally = checkBouncyTurns(options, decode);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    print(what, tally, ms);
    return tally;
}

void expectExact(const BounceTally& tally, std::int64_t transitions) {
    EXPECT_GE(tally.transitions, transitions);
    EXPECT_GT(tally.chatterEdges, tally.transitions);  // bursts of 0–4 pairs: ~4 per transition
    EXPECT_GT(tally.abortedTurns, 0);
    EXPECT_GT(tally.intended, 0);
    EXPECT_EQ(tally.lost, 0);
    EXPECT_EQ(tally.phantom, 0);
    EXPECT_EQ(tally.positionMismatches, 0);
    EXPECT_EQ(tally.decoded, tally.intended);
}

TEST(BounceTest, AMillionBouncyTransitionsLoseAndInventNoDetent) {
    QuadratureDecoder decoder(4);
    const BounceTally tally =
        runTimed("4 steps/detent", bouncyTurns(20240607, 4, 1'000'000), decoderUnderTest(decoder));
    expectExact(tally, 1'000'000);
    EXPECT_EQ(decoder.detents(), decoder.transitions() / 4);
}

TEST(BounceTest, HalfCycleEncodersAreImmuneToo) {
    QuadratureDecoder decoder(2);
    expectExact(runTimed("2 steps/detent", bouncyTurns(7, 2, 1'000'000), decoderUnderTest(decoder)),
                1'000'000);
}

// At one step per detent every transition is a detent: chatter shows as +1/−1 pairs that
// cancel. Nothing is lost and the position is right at every boundary, but phantoms exist: the
// documented reason to use 2 or 4 steps per detent.
TEST(BounceTest, OneStepPerDetentCancelsChatterButReportsIt) {
    QuadratureDecoder decoder(1);
    const BounceTally tally =
        runTimed("1 step/detent", bouncyTurns(11, 1, 100'000), decoderUnderTest(decoder));
    EXPECT_EQ(tally.lost, 0);
    EXPECT_EQ(tally.positionMismatches, 0);
    EXPECT_GT(tally.phantom, 0);
}

// The check can fail: a decoder that counts every falling edge of A (direction from B), as a
// naive interrupt handler does, is caught inventing detents.
TEST(BounceTest, TheCheckCatchesANaiveDecoder) {
    bool previousA = true;
    const testing::DecodeFn naive = [&previousA](const ScriptEdge&, bool a, bool b) {
        const int reported = previousA && !a ? (b ? 1 : -1) : 0;
        previousA = a;
        return reported;
    };
    BouncyTurnsOptions options;
    options.transitions = 100'000;
    const BounceTally tally = checkBouncyTurns(options, naive);
    print("naive decoder", tally, 0);
    EXPECT_GT(tally.phantom, 1000);
    EXPECT_GT(tally.positionMismatches, 1000);
}

// The check can fail: one intended edge dropped (as if the kernel lost the event) loses a detent
// and shifts the position for the rest of the script; the same script without the drop passes.
TEST(BounceTest, TheCheckCatchesOneDroppedEdge) {
    BouncyTurnsOptions options;
    options.seed = 3;
    options.transitions = 20'000;
    QuadratureDecoder clean(4);
    expectExact(checkBouncyTurns(options, decoderUnderTest(clean)), 20'000);

    options.dropTransition = 10'001;
    QuadratureDecoder dropped(4);
    const BounceTally tally = checkBouncyTurns(options, decoderUnderTest(dropped));
    print("one dropped edge", tally, 0);
    EXPECT_GE(tally.lost + tally.phantom, 1);
    EXPECT_GT(tally.positionMismatches, 1000);
}

// The same walk as GPIO edges through the KnobEdgeSink, the single decoding path of the
// hardware backend and of replay.
TEST(BounceTest, TheEdgeSinkDecodesBouncyEdges) {
    KnobsConfig config;
    config.enabled = true;
    config.encoders.push_back(EncoderConfig{17, 27, KnobAxis::kAzimuth, 1.5, 4, false, {}});
    KnobEdgeSink sink(config, {}, 0);
    std::vector<InputEvent> events;
    const testing::DecodeFn viaSink = [&](const ScriptEdge& edge, bool, bool) {
        events.clear();
        const LineEdge lineEdge{edge.contact == Contact::kA ? 17U : 27U,
                                edge.level ? EdgeKind::kRising : EdgeKind::kFalling,
                                edge.timestampNs};
        EXPECT_TRUE(sink.onEdge(lineEdge, events));
        if (events.empty()) {
            return 0;
        }
        EXPECT_EQ(events.size(), 1U);
        EXPECT_EQ(events[0].timestampNs, edge.timestampNs);
        EXPECT_EQ(events[0].source, InputSource::kKnobs);
        const double azimuth = std::get<TurnLight>(events[0].action).azimuthDeg;
        EXPECT_EQ(std::abs(azimuth), 1.5);
        return azimuth > 0 ? 1 : -1;
    };
    BouncyTurnsOptions options;
    options.seed = 99;
    options.transitions = 200'000;
    expectExact(runTimed("edge sink", options, viaSink), 200'000);
}

}  // namespace
}  // namespace vpe::firmware::knobs
