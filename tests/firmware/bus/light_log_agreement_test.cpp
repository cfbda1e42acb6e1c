// SPDX-License-Identifier: MIT
// The measures the multi-node tests and scripts/multi-node-report.sh judge the nodes by, on
// tracks whose answer is known: a copy lags 0, a copy 5 ms late lags 5 ms, a different still
// light is apart, a motion's start is found, a gap is seen.
#include "light_log_agreement.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <unistd.h>

namespace vpe::firmware::bus::testing {
namespace {

constexpr std::int64_t kFrameUs = 16'667;

// Still until 1 s, then an exponential approach of 20° (τ 0.12 s), sampled at 60 Hz from
// `phaseUs`, `lateUs` behind.
LightTrack steppingTrack(std::int64_t phaseUs, std::int64_t lateUs, double offsetDeg = 0) {
    LightTrack track;
    for (std::int64_t t = phaseUs; t < 3'000'000; t += kFrameUs) {
        const double since = static_cast<double>(t - lateUs - 1'000'000) * 1e-6;
        const double az = since <= 0 ? 0 : 20.0 * (1.0 - std::exp(-since / 0.12));
        track.push_back({t, az + offsetDeg, 30.0, 0.6, "knobs"});
    }
    return track;
}

TEST(LightLogAgreementTest, MeasuresLagsInTime) {
    const LightTrack reference = steppingTrack(0, 0);
    const Agreement same = compareTracks(reference, steppingTrack(7'000, 0), 200'000, 2'800'000);
    ASSERT_GT(same.lagsMs.size(), 100u);
    EXPECT_EQ(same.apart, 0u);
    EXPECT_LE(same.percentile(0.99), 0.5);  // other frame times, the same light

    const Agreement late =
        compareTracks(reference, steppingTrack(7'000, 5'000), 200'000, 2'800'000);
    EXPECT_EQ(late.apart, 0u);
    // While it moves fast the lag shows (a little less where the path bends, the allowance);
    // still, before and long after, it does not.
    EXPECT_GT(late.percentile(1.0), 3.5);  // 5 ms, less the allowance's blur (≤ 1.2 ms)
    EXPECT_LE(late.percentile(1.0), 5.25);
    EXPECT_EQ(late.percentile(0.2), 0.0);

    const Agreement elsewhere =
        compareTracks(reference, steppingTrack(7'000, 0, 0.5), 200'000, 800'000);
    EXPECT_EQ(elsewhere.apart, elsewhere.lagsMs.size());
    EXPECT_EQ(elsewhere.percentile(0.5), 100.0);  // the window
}

TEST(LightLogAgreementTest, FindsWhenATrackSettlesAndStartsMoving) {
    const LightTrack reference = steppingTrack(0, 0);
    LightTrack wrongThenRight = steppingTrack(7'000, 0);
    for (LightSample& s : wrongThenRight) {
        if (s.tUs < 1'500'000) {
            s.elevationDeg = 40;
        }
    }
    const auto settled = settledFrom(reference, wrongThenRight, 1'200'000, 2'800'000, 16.7);
    ASSERT_TRUE(settled.has_value());
    EXPECT_GE(*settled, 1'500'000);
    EXPECT_LT(*settled, 1'500'000 + kFrameUs);

    const std::vector<std::int64_t> onsets = motionOnsets(reference);
    ASSERT_EQ(onsets.size(), 1u);
    EXPECT_GE(onsets[0], 1'000'000);
    EXPECT_LT(onsets[0], 1'000'000 + kFrameUs);

    LightTrack gap = reference;
    gap.erase(gap.begin() + 30, gap.begin() + 42);
    EXPECT_NEAR(largestGapMs(gap, 0, 3'000'000), 13 * 16.667, 0.1);
    EXPECT_NEAR(largestGapMs(reference, 0, 3'000'000), 16.667, 0.01);
}

// A lone frame presented late (its light right, its time slipped by 40 ms) between frames that
// agree does not unsettle a track; two late frames in a row do.
TEST(LightLogAgreementTest, ALoneLateFrameDoesNotUnsettle) {
    const LightTrack reference = steppingTrack(0, 0);
    const auto lateAt = [](LightTrack track, std::int64_t fromUs, int frames) {
        for (LightSample& s : track) {
            if (s.tUs >= fromUs && frames > 0) {
                s.tUs += 40'000;  // each frame is judged on its own: order does not matter
                --frames;
            }
        }
        return track;
    };
    // While the light moves (1.0-1.6 s), where a time slip shows as a lag.
    const LightTrack once = lateAt(steppingTrack(7'000, 0), 1'100'000, 1);
    const auto settledOnce = settledFrom(reference, once, 200'000, 2'800'000, 16.7);
    ASSERT_TRUE(settledOnce.has_value());
    EXPECT_LT(*settledOnce, 200'000 + kFrameUs);

    const LightTrack twice = lateAt(steppingTrack(7'000, 0), 1'100'000, 2);
    const auto settledTwice = settledFrom(reference, twice, 200'000, 2'800'000, 16.7);
    ASSERT_TRUE(settledTwice.has_value());
    EXPECT_GT(*settledTwice, 1'100'000);
}

TEST(LightLogAgreementTest, ReadsALightLog) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("vpe-light-log-" + std::to_string(::getpid()));
    std::ofstream(path)
        << "{\"t_us\": 100, \"azimuth\": 1.5, \"elevation\": 30.000000, \"distance\": 0.6, "
           "\"active\": \"bus\", \"drawn\": true}\n"
           "{\"t_us\": 200, \"azimuth\": 2.5, \"elevation\": 30.000000, \"distance\": 0.6, "
           "\"active\": \"idle\", \"drawn\": false}\n"
           "{\"t_us\": 30";  // cut short by a kill
    const LightTrack track = readLightLog(path);
    ASSERT_EQ(track.size(), 2u);
    EXPECT_EQ(track[1].active, "idle");
    EXPECT_EQ(lightAt(track, 150)->azimuthDeg, 2.0);
    EXPECT_FALSE(lightAt(track, 250).has_value());
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace vpe::firmware::bus::testing
