// SPDX-License-Identifier: MIT
// DebouncedButton: chatter shorter than the debounce time is ignored, a press held for it fires
// once (stamped with the edge that began it), releases never fire, active-high works too.
#include "vpe/firmware/knobs/debounced_button.h"

#include <gtest/gtest.h>

namespace vpe::firmware::knobs {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(DebouncedButtonTest, ChatterShorterThanTheDebounceIsIgnored) {
    DebouncedButton button(20 * kMs, true, true, 0);
    // A glitch: low for 3 ms, high again; bursts under 20 ms, then nothing.
    EXPECT_FALSE(button.onEdge(false, 100 * kMs));
    EXPECT_FALSE(button.onEdge(true, 103 * kMs));
    EXPECT_FALSE(button.onEdge(false, 110 * kMs));
    EXPECT_FALSE(button.onEdge(true, 125 * kMs));
    for (std::int64_t t = 125; t < 400; t += 5) {
        EXPECT_FALSE(button.onTick(t * kMs));
    }
    EXPECT_FALSE(button.pressed());
}

TEST(DebouncedButtonTest, APressStableForTheDebounceFiresOnce) {
    DebouncedButton button(20 * kMs, true, true, 0);
    // Press with bounce: the last change is at 104 ms; stable from there.
    EXPECT_FALSE(button.onEdge(false, 100 * kMs));
    EXPECT_FALSE(button.onEdge(true, 101 * kMs));
    EXPECT_FALSE(button.onEdge(false, 104 * kMs));
    EXPECT_FALSE(button.onTick(123 * kMs));  // 19 ms: not yet
    const std::optional<std::int64_t> press = button.onTick(124 * kMs);
    ASSERT_TRUE(press.has_value());
    EXPECT_EQ(*press, 104 * kMs);
    EXPECT_TRUE(button.pressed());
    EXPECT_FALSE(button.onTick(200 * kMs));  // once
    // Release with bounce: no event, and the button is released after it settles.
    EXPECT_FALSE(button.onEdge(true, 300 * kMs));
    EXPECT_FALSE(button.onEdge(false, 302 * kMs));
    EXPECT_FALSE(button.onEdge(true, 305 * kMs));
    EXPECT_FALSE(button.onTick(400 * kMs));
    EXPECT_FALSE(button.pressed());
    // A second press fires again.
    EXPECT_FALSE(button.onEdge(false, 500 * kMs));
    EXPECT_EQ(button.onTick(520 * kMs), 500 * kMs);
}

TEST(DebouncedButtonTest, ANextEdgeSettlesWithoutATick) {
    // Replay may feed edges with no tick between: the press settles on the release's edge.
    DebouncedButton button(20 * kMs, true, true, 0);
    EXPECT_FALSE(button.onEdge(false, 100 * kMs));
    EXPECT_EQ(button.onEdge(true, 180 * kMs), 100 * kMs);
    EXPECT_FALSE(button.onTick(1000 * kMs));
}

TEST(DebouncedButtonTest, ActiveHighAndZeroDebounce) {
    DebouncedButton button(0, false, false, 0);
    EXPECT_EQ(button.onEdge(true, 5), 5);  // high is pressed; no wait
    EXPECT_FALSE(button.onEdge(false, 6));
    EXPECT_EQ(button.onEdge(true, 7), 7);
}

TEST(DebouncedButtonTest, AButtonHeldAtStartDoesNotFire) {
    DebouncedButton button(20 * kMs, true, false, 0);
    EXPECT_TRUE(button.pressed());
    EXPECT_FALSE(button.onTick(1000 * kMs));
    EXPECT_FALSE(button.onEdge(true, 1000 * kMs));
    EXPECT_FALSE(button.onTick(2000 * kMs));
    EXPECT_EQ(button.onEdge(false, 3000 * kMs), std::nullopt);
    EXPECT_EQ(button.onTick(3020 * kMs), 3000 * kMs);
}

}  // namespace
}  // namespace vpe::firmware::knobs
