// SPDX-License-Identifier: MIT
// OscDispatcher: every address of proto/OSC.md, the numeric coercions, and every rejection
// reason counted under its own name and logged at a rate a flood cannot raise.
#include "vpe/firmware/osc/osc_dispatcher.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

struct Fixture {
    std::vector<std::string> lines;
    OscDispatcher dispatcher{OscLimits{},
                             [this](const std::string& line) { lines.push_back(line); }};

    Fixture() { dispatcher.setPresetNames({"marble", "brass", "velvet"}); }

    OscOutcome send(std::string_view path, std::vector<OscArgument> arguments,
                    std::int64_t timestampNs = 42) {
        return dispatcher.dispatch(path, arguments, timestampNs);
    }
};

AimLight aimOf(const OscOutcome& outcome) {
    EXPECT_TRUE(outcome.accepted()) << outcome.problem;
    EXPECT_TRUE(outcome.event.has_value());
    if (!outcome.event) {
        return {};
    }
    const auto* aim = std::get_if<AimLight>(&outcome.event->action);
    EXPECT_NE(aim, nullptr);
    return aim != nullptr ? *aim : AimLight{};
}

TEST(OscDispatcherTest, AimsTheLightWithEveryNumericType) {
    Fixture f;
    // i, h, f, d are all numbers (senders differ: Max sends i for integers, QLab f, …).
    EXPECT_EQ(aimOf(f.send("/vpe/light/azimuth", {30.0f})).azimuthDeg, 30.0);
    EXPECT_EQ(aimOf(f.send("/vpe/light/azimuth", {std::int32_t{-45}})).azimuthDeg, -45.0);
    EXPECT_EQ(aimOf(f.send("/vpe/light/azimuth", {std::int64_t{180}})).azimuthDeg, 180.0);
    EXPECT_EQ(aimOf(f.send("/vpe/light/azimuth", {-180.0})).azimuthDeg, -180.0);

    const AimLight azimuth = aimOf(f.send("/vpe/light/azimuth", {12.5}));
    EXPECT_FALSE(azimuth.elevationDeg.has_value());
    EXPECT_FALSE(azimuth.distanceM.has_value());

    const AimLight elevation = aimOf(f.send("/vpe/light/elevation", {std::int32_t{90}}));
    EXPECT_EQ(elevation.elevationDeg, 90.0);
    EXPECT_FALSE(elevation.azimuthDeg.has_value());

    EXPECT_EQ(aimOf(f.send("/vpe/light/distance", {0.75f})).distanceM, 0.75);

    const AimLight direction = aimOf(f.send("/vpe/light/direction", {std::int32_t{10}, 20.5f}));
    EXPECT_EQ(direction.azimuthDeg, 10.0);
    EXPECT_EQ(direction.elevationDeg, 20.5);
    EXPECT_FALSE(direction.distanceM.has_value());

    EXPECT_EQ(f.dispatcher.counters().accepted, 8u);
    EXPECT_EQ(f.dispatcher.counters().rejectedTotal(), 0u);
    EXPECT_TRUE(f.lines.empty());
}

TEST(OscDispatcherTest, StampsEventsWithTheSourceAndArrivalTime) {
    Fixture f;
    const OscOutcome outcome = f.send("/vpe/light/azimuth", {1.0f}, 123'456'789);
    ASSERT_TRUE(outcome.event.has_value());
    EXPECT_EQ(outcome.event->source, InputSource::kOsc);
    EXPECT_EQ(outcome.event->timestampNs, 123'456'789);
    EXPECT_FALSE(outcome.reply.has_value());
}

TEST(OscDispatcherTest, PlacesResetsAndSelectsPresets) {
    Fixture f;
    const OscOutcome place = f.send("/vpe/light/position", {0.5f, std::int32_t{1}, -0.25});
    ASSERT_TRUE(place.event.has_value()) << place.problem;
    const auto& position = std::get<PlaceLight>(place.event->action).position;
    EXPECT_EQ(position, (std::array<double, 3>{0.5, 1.0, -0.25}));

    const OscOutcome reset = f.send("/vpe/light/reset", {});
    ASSERT_TRUE(reset.event.has_value());
    EXPECT_TRUE(std::holds_alternative<ResetLight>(reset.event->action));

    const auto preset = [&](std::vector<OscArgument> arguments) {
        const OscOutcome outcome = f.send("/vpe/weights/preset", std::move(arguments));
        EXPECT_TRUE(outcome.event.has_value()) << outcome.problem;
        return outcome.event ? std::get<SelectPreset>(outcome.event->action) : SelectPreset{-9};
    };
    EXPECT_EQ(preset({std::int32_t{2}}).value, 2);
    EXPECT_FALSE(preset({std::int32_t{2}}).relative);
    EXPECT_EQ(preset({std::int64_t{0}}).value, 0);
    EXPECT_EQ(preset({1.0f}).value, 1);  // TouchDesigner sends floats
    EXPECT_EQ(preset({std::string("velvet")}).value, 2);
    EXPECT_EQ(preset({std::string("marble")}).value, 0);

    const OscOutcome next = f.send("/vpe/weights/next", {});
    ASSERT_TRUE(next.event.has_value());
    EXPECT_EQ(std::get<SelectPreset>(next.event->action).value, 1);
    EXPECT_TRUE(std::get<SelectPreset>(next.event->action).relative);
    const OscOutcome previous = f.send("/vpe/weights/previous", {});
    ASSERT_TRUE(previous.event.has_value());
    EXPECT_EQ(std::get<SelectPreset>(previous.event->action).value, -1);
    EXPECT_TRUE(std::get<SelectPreset>(previous.event->action).relative);

    EXPECT_EQ(f.dispatcher.counters().accepted, 10u);
}

TEST(OscDispatcherTest, AnswersQueriesWithoutEvents) {
    Fixture f;
    const OscOutcome status = f.send("/vpe/status", {});
    EXPECT_TRUE(status.accepted());
    EXPECT_FALSE(status.event.has_value());
    ASSERT_TRUE(status.reply.has_value());
    EXPECT_EQ(status.reply->query, OscQuery::kStatus);
    EXPECT_FALSE(status.reply->port.has_value());

    const OscOutcome ping = f.send("/vpe/ping", {std::int32_t{9001}});
    ASSERT_TRUE(ping.reply.has_value());
    EXPECT_EQ(ping.reply->query, OscQuery::kPing);
    EXPECT_EQ(ping.reply->port, 9001);
    EXPECT_EQ(f.send("/vpe/status", {9002.0f}).reply->port, 9002);
    EXPECT_EQ(f.dispatcher.counters().accepted, 3u);
}

TEST(OscDispatcherTest, RefusesEachFaultUnderItsOwnReason) {
    Fixture f;
    struct Case {
        std::string path;
        std::vector<OscArgument> arguments;
        OscRejection reason;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<Case> cases{
        {"/vpe/light/azimuthx", {1.0f}, OscRejection::kUnknownAddress},
        {"/vpe/light/*", {1.0f}, OscRejection::kUnknownAddress},  // patterns are not expanded
        {"", {}, OscRejection::kUnknownAddress},
        {"/vpe/light/azimuth", {}, OscRejection::kArgumentCount},
        {"/vpe/light/azimuth", {1.0f, 2.0f}, OscRejection::kArgumentCount},
        {"/vpe/light/direction", {1.0f}, OscRejection::kArgumentCount},
        {"/vpe/light/position", {1.0f, 2.0f}, OscRejection::kArgumentCount},
        {"/vpe/light/reset", {std::int32_t{1}}, OscRejection::kArgumentCount},
        {"/vpe/weights/next", {1.0f}, OscRejection::kArgumentCount},
        {"/vpe/weights/preset", {}, OscRejection::kArgumentCount},
        {"/vpe/status", {std::int32_t{1}, std::int32_t{2}}, OscRejection::kArgumentCount},
        {"/vpe/light/azimuth", {std::string("30")}, OscRejection::kArgumentType},
        {"/vpe/light/direction", {1.0f, OscOtherArgument{'b'}}, OscRejection::kArgumentType},
        {"/vpe/light/elevation", {OscOtherArgument{'T'}}, OscRejection::kArgumentType},
        {"/vpe/weights/preset", {1.5f}, OscRejection::kArgumentType},
        {"/vpe/weights/preset", {OscOtherArgument{'N'}}, OscRejection::kArgumentType},
        {"/vpe/ping", {std::string("9000")}, OscRejection::kArgumentType},
        {"/vpe/light/azimuth", {nan}, OscRejection::kNotFinite},
        {"/vpe/light/elevation", {inf}, OscRejection::kNotFinite},
        {"/vpe/light/distance", {-inf}, OscRejection::kNotFinite},
        {"/vpe/light/position", {0.0f, nan, 0.0f}, OscRejection::kNotFinite},
        {"/vpe/weights/preset", {nan}, OscRejection::kNotFinite},
        {"/vpe/light/azimuth", {180.5f}, OscRejection::kOutOfRange},
        {"/vpe/light/azimuth", {std::int32_t{-181}}, OscRejection::kOutOfRange},
        {"/vpe/light/elevation", {90.01}, OscRejection::kOutOfRange},
        {"/vpe/light/distance", {0.0f}, OscRejection::kOutOfRange},
        {"/vpe/light/distance", {std::int32_t{-1}}, OscRejection::kOutOfRange},
        {"/vpe/light/direction", {0.0f, -91.0f}, OscRejection::kOutOfRange},
        {"/vpe/light/position", {0.0f, 0.0f, 100.5f}, OscRejection::kOutOfRange},
        {"/vpe/weights/preset", {std::int32_t{3}}, OscRejection::kOutOfRange},
        {"/vpe/weights/preset", {std::int32_t{-1}}, OscRejection::kOutOfRange},
        {"/vpe/weights/preset", {std::int64_t{1} << 40}, OscRejection::kOutOfRange},
        {"/vpe/status", {std::int32_t{0}}, OscRejection::kOutOfRange},
        {"/vpe/ping", {std::int32_t{65536}}, OscRejection::kOutOfRange},
        {"/vpe/weights/preset", {std::string("Marble")}, OscRejection::kUnknownPreset},
        {"/vpe/weights/preset", {std::string("")}, OscRejection::kUnknownPreset},
    };
    std::array<std::uint64_t, kOscRejectionCount> expected{};
    for (const Case& c : cases) {
        const OscOutcome outcome = f.send(c.path, c.arguments);
        ASSERT_TRUE(outcome.rejection.has_value()) << c.path << " " << oscTypeTags(c.arguments);
        EXPECT_EQ(*outcome.rejection, c.reason) << c.path << ": " << outcome.problem << " ("
                                                << oscRejectionName(*outcome.rejection) << ")";
        EXPECT_FALSE(outcome.event.has_value());
        EXPECT_FALSE(outcome.reply.has_value());
        ++expected[static_cast<std::size_t>(c.reason)];
    }
    f.dispatcher.rejectMalformed("datagram of 3 bytes: not an OSC message", 42);
    ++expected[static_cast<std::size_t>(OscRejection::kMalformedPacket)];
    f.dispatcher.rejectSource("datagram of 20 bytes from 10.1.2.3:5000: not in [osc] allow", 43);
    ++expected[static_cast<std::size_t>(OscRejection::kSourceNotAllowed)];

    EXPECT_EQ(f.dispatcher.counters().rejected, expected);
    EXPECT_EQ(f.dispatcher.counters().rejectedTotal(), cases.size() + 2);
    EXPECT_EQ(f.dispatcher.counters().accepted, 0u);
    for (std::size_t reason = 0; reason < kOscRejectionCount; ++reason) {
        EXPECT_GT(expected[reason], 0u) << oscRejectionName(static_cast<OscRejection>(reason));
    }
}

TEST(OscDispatcherTest, SaysWhatIsWrongInOneLine) {
    Fixture f;
    EXPECT_EQ(f.send("/vpe/light/azimuth", {270.0f}).problem,
              "/vpe/light/azimuth f: azimuth 270 is outside [-180, 180]");
    EXPECT_EQ(f.send("/vpe/light/distance", {std::int32_t{0}}).problem,
              "/vpe/light/distance i: distance 0 is outside [0, inf] (must be above 0)");
    EXPECT_EQ(f.send("/vpe/light/direction", {1.0f, std::string("up")}).problem,
              "/vpe/light/direction fs: argument 2 is 's', expected a number (i, h, f, d)");
    EXPECT_EQ(f.send("/vpe/light/reset", {1.0f}).problem,
              "/vpe/light/reset f: expected no arguments, got 1");
    EXPECT_EQ(f.send("/vpe/light/elevation", {}).problem,
              "/vpe/light/elevation: expected 1 number, got 0 arguments");
    EXPECT_EQ(f.send("/vpe/weights/preset", {std::string("gold")}).problem,
              "/vpe/weights/preset s: no preset named \"gold\" (3 presets)");
    EXPECT_EQ(f.send("/vpe/weights/preset", {std::int32_t{7}}).problem,
              "/vpe/weights/preset i: index 7 is outside [0, 2] (3 presets)");
    // Addresses come off the network: control bytes never reach the journal raw.
    EXPECT_EQ(f.send("/x\x1b[2J\n", {}).problem, "/x\\x1b[2J\\x0a: unknown address");
    ASSERT_EQ(f.lines.size(), 5u);  // the burst; the rest are counted, not logged
    EXPECT_EQ(f.lines[0],
              "osc: /vpe/light/azimuth f: azimuth 270 is outside [-180, 180] "
              "(out_of_range)");
    EXPECT_EQ(f.dispatcher.unloggedRejections(), 3u);
}

TEST(OscDispatcherTest, AppliesTheBoardsLimitsWithinTheHardRanges) {
    Fixture f;
    OscLimits limits;
    limits.azimuthDeg = {-60.0, 60.0};
    limits.elevationDeg = {-10.0, 120.0};  // wider than the hard range: clipped to 90
    limits.distanceM = {0.5, 3.0};
    limits.positionExtentM = 2.0;
    f.dispatcher.setLimits(limits);
    EXPECT_EQ(f.dispatcher.limits().elevationDeg, (std::pair{-10.0, 90.0}));

    EXPECT_TRUE(f.send("/vpe/light/azimuth", {60.0f}).accepted());
    EXPECT_EQ(f.send("/vpe/light/azimuth", {61.0f}).rejection, OscRejection::kOutOfRange);
    EXPECT_EQ(f.send("/vpe/light/elevation", {-11.0f}).rejection, OscRejection::kOutOfRange);
    EXPECT_EQ(f.send("/vpe/light/elevation", {95.0f}).rejection, OscRejection::kOutOfRange);
    EXPECT_TRUE(f.send("/vpe/light/distance", {0.5f}).accepted());
    EXPECT_EQ(f.send("/vpe/light/distance", {0.4f}).rejection, OscRejection::kOutOfRange);
    EXPECT_EQ(f.send("/vpe/light/distance", {3.5f}).rejection, OscRejection::kOutOfRange);
    EXPECT_EQ(f.send("/vpe/light/direction", {70.0f, 0.0f}).rejection, OscRejection::kOutOfRange);
    EXPECT_TRUE(f.send("/vpe/light/position", {2.0f, -2.0f, 0.0f}).accepted());
    EXPECT_EQ(f.send("/vpe/light/position", {2.5f, 0.0f, 0.0f}).rejection,
              OscRejection::kOutOfRange);
    EXPECT_EQ(f.dispatcher.counters().accepted, 3u);
    EXPECT_EQ(f.dispatcher.counters().rejectedFor(OscRejection::kOutOfRange), 7u);
}

TEST(OscDispatcherTest, RefusesPresetsUntilToldTheBundlesNames) {
    OscDispatcher dispatcher(OscLimits{}, [](const std::string&) {});
    const std::vector<OscArgument> zero{std::int32_t{0}};
    EXPECT_EQ(dispatcher.dispatch("/vpe/weights/preset", zero, 0).rejection,
              OscRejection::kOutOfRange);
    dispatcher.setPresetNames({"only"});
    EXPECT_TRUE(dispatcher.dispatch("/vpe/weights/preset", zero, 0).accepted());
}

TEST(OscDispatcherTest, FloodOfRejectionsIsCountedButBarelyLogged) {
    Fixture f;
    for (int i = 0; i < 10'000; ++i) {
        // 1 ms apart: the whole flood lasts 10 s.
        f.send("/vpe/light/azimuth", {999.0f}, i * 1'000'000LL);
    }
    EXPECT_EQ(f.dispatcher.counters().rejectedFor(OscRejection::kOutOfRange), 10'000u);
    // 5 at once; the bucket earns its next line 10 s after the first, just after the flood.
    EXPECT_EQ(f.lines.size(), 5u);
    EXPECT_EQ(f.dispatcher.unloggedRejections(), 9'995u);
    f.send("/vpe/light/azimuth", {999.0f}, 10 * kSecond);
    ASSERT_EQ(f.lines.size(), 6u);
    EXPECT_NE(f.lines.back().find("(9995 earlier not logged)"), std::string::npos)
        << f.lines.back();
}

}  // namespace
}  // namespace vpe::firmware
