// SPDX-License-Identifier: MIT
// LightMessage: the retained state's JSON both ways, and everything the reader refuses, each
// under its reason (a refused message never moves the light).
#include "vpe/firmware/bus/light_message.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bus_test_limits.h"

namespace vpe::firmware::bus {
namespace {

LightLimits limits() {
    return testing::busTestLimits();
}

LightMessage sample() {
    LightMessage m;
    m.node = "vpe-pi-left";
    m.seq = 42;
    m.timeUs = 1'718'000'000'123'456;
    m.target = {20.5, 35.25, 0.6};
    m.from = {12.125, 33.0, 0.6};
    m.fromUs = 1'718'000'000'120'000;
    m.driftUs = 1'718'000'060'120'000;
    m.preset = "stripes";
    m.source = "knobs";
    return m;
}

TEST(LightMessageTest, RoundTrips) {
    const LightMessage m = sample();
    const std::string text = encodeLightMessage(m);
    // The documented shape (proto/BUS.md), keys in their documented order.
    EXPECT_EQ(text.substr(0, 58),
              "{\"format\":1,\"node\":\"vpe-pi-left\",\"seq\":42,\"time_us\":171800");
    const auto decoded = decodeLightMessage(text, limits());
    ASSERT_TRUE(std::holds_alternative<LightMessage>(decoded))
        << std::get<LightMessageRefusal>(decoded).reason;
    const LightMessage& d = std::get<LightMessage>(decoded);
    EXPECT_EQ(d.node, m.node);
    EXPECT_EQ(d.seq, m.seq);
    EXPECT_EQ(d.timeUs, m.timeUs);
    EXPECT_EQ(d.target.azimuthDeg, 20.5);
    EXPECT_EQ(d.target.elevationDeg, 35.25);
    EXPECT_EQ(d.target.distanceM, 0.6);
    EXPECT_EQ(d.from.azimuthDeg, 12.125);
    EXPECT_EQ(d.fromUs, m.fromUs);
    EXPECT_EQ(d.driftUs, m.driftUs);
    EXPECT_EQ(d.preset, "stripes");
    EXPECT_EQ(d.source, "knobs");

    LightMessage never = m;
    never.driftUs.reset();
    never.preset.clear();
    const std::string noDrift = encodeLightMessage(never);
    EXPECT_NE(noDrift.find("\"drift_us\":null"), std::string::npos) << noDrift;
    const auto back = decodeLightMessage(noDrift, limits());
    ASSERT_TRUE(std::holds_alternative<LightMessage>(back));
    EXPECT_FALSE(std::get<LightMessage>(back).driftUs.has_value());
    EXPECT_TRUE(std::get<LightMessage>(back).preset.empty());
}

TEST(LightMessageTest, RefusesWhatItCannotTrust) {
    const nlohmann::json good = nlohmann::json::parse(encodeLightMessage(sample()));
    struct Case {
        std::string payload;
        LightMessageProblem problem;
        std::string reason;
    };
    const auto with = [&](const std::function<void(nlohmann::json&)>& change) {
        nlohmann::json j = good;
        change(j);
        return j.dump();
    };
    using P = LightMessageProblem;
    const std::vector<Case> cases{
        {"", P::kMalformed, "not JSON"},
        {"{\"format\": 1,", P::kMalformed, "not JSON"},
        {"[1, 2]", P::kMalformed, "expected a JSON object, got array"},
        {std::string(5000, ' '), P::kMalformed,
         "a payload of 5000 bytes (a light state is at most 4096)"},
        {with([](auto& j) { j["format"] = 2; }), P::kMalformed,
         "format 2: this node reads format 1"},
        {with([](auto& j) { j.erase("azimuth"); }), P::kMalformed, "\"azimuth\" is missing"},
        {with([](auto& j) { j["from"].erase("time_us"); }), P::kMalformed,
         "\"from.time_us\" is missing"},
        {with([](auto& j) { j["elevation"] = "high"; }), P::kMalformed,
         "\"elevation\": expected a number, got string"},
        {with([](auto& j) { j["seq"] = -1; }), P::kMalformed,
         "\"seq\": expected a whole number from 0, got -1"},
        {with([](auto& j) { j["time_us"] = 1.5e15; }), P::kMalformed,
         "\"time_us\": expected whole microseconds, got number"},
        {with([](auto& j) { j["node"] = ""; }), P::kMalformed, "\"node\" is empty"},
        {with([](auto& j) { j["node"] = 7; }), P::kMalformed,
         "\"node\": expected a string, got number"},
        {with([](auto& j) { j["from"] = 3; }), P::kMalformed,
         "\"from\": expected an object, got number"},
        {with([](auto& j) { j["azimuth"] = 270; }), P::kOutOfRange,
         "azimuth 270 is outside [-100, 100]"},
        {with([](auto& j) { j["from"]["elevation"] = 85; }), P::kOutOfRange,
         "from.elevation 85 is outside [5, 80]"},
        {with([](auto& j) { j["distance"] = 9; }), P::kOutOfRange,
         "distance 9 is outside [0.3, 1.5]"},
        {"{\"format\":1,\"node\":\"n\",\"seq\":1,\"time_us\":1718000000000000,\"azimuth\":1e999,"
         "\"elevation\":30,\"distance\":0.6,\"from\":{\"time_us\":1718000000000000,\"azimuth\":0,"
         "\"elevation\":30,\"distance\":0.6}}",
         P::kMalformed, "not JSON"},  // JSON has no infinity: nlohmann refuses the overflow
        {with([](auto& j) { j["time_us"] = 12345; }), P::kOutOfRange,
         "\"time_us\" 12345 is not a time of the wall clock in microseconds"},
        {with([](auto& j) { j["from"]["time_us"] = 1'718'000'001'000'000; }), P::kOutOfRange,
         "from.time_us is after time_us (a move cannot start after the state was made)"},
        {with([](auto& j) { j["drift_us"] = 1'718'000'000'000'000; }), P::kOutOfRange,
         "drift_us is before from.time_us (the drift starts after the move)"},
    };
    for (const Case& c : cases) {
        const auto decoded = decodeLightMessage(c.payload, limits());
        ASSERT_TRUE(std::holds_alternative<LightMessageRefusal>(decoded)) << c.payload;
        const auto& refusal = std::get<LightMessageRefusal>(decoded);
        EXPECT_EQ(refusal.problem, c.problem) << c.payload;
        EXPECT_EQ(refusal.reason, c.reason) << c.payload;
    }
    // A full-circle board takes any azimuth of the hard range; unknown keys are for later
    // formats to add and are read past.
    LightLimits full = limits();
    full.azimuthDeg = {-180, 180};
    EXPECT_TRUE(std::holds_alternative<LightMessage>(decodeLightMessage(with([](auto& j) {
                                                                            j["azimuth"] = 179.5;
                                                                            j["colour"] = "warm";
                                                                        }),
                                                                        full)));
}

}  // namespace
}  // namespace vpe::firmware::bus
