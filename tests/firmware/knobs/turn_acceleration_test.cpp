// SPDX-License-Identifier: MIT
// Turn acceleration: the ramp between slow and fast, and what counts as a fast turn.
#include "vpe/firmware/knobs/turn_acceleration.h"

#include <gtest/gtest.h>

namespace vpe::firmware::knobs {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(TurnAccelerationTest, RampsLinearlyBetweenSlowAndFast) {
    const AccelerationCurve curve{100, 20, 5};
    EXPECT_EQ(accelerationFactor(curve, 500), 1);
    EXPECT_EQ(accelerationFactor(curve, 100), 1);
    EXPECT_DOUBLE_EQ(accelerationFactor(curve, 60), 3);
    EXPECT_DOUBLE_EQ(accelerationFactor(curve, 80), 2);
    EXPECT_EQ(accelerationFactor(curve, 20), 5);
    EXPECT_EQ(accelerationFactor(curve, 1), 5);
    EXPECT_EQ(accelerationFactor(curve, -3), 5);
    // Monotonic: faster never moves less.
    double previous = 0;
    for (double ms = 200; ms >= 0; ms -= 0.5) {
        const double factor = accelerationFactor(curve, ms);
        EXPECT_GE(factor, previous);
        previous = factor;
    }
}

TEST(TurnAccelerationTest, AFactorOfOneIsOff) {
    const AccelerationCurve off{100, 20, 1};
    EXPECT_EQ(accelerationFactor(off, 0), 1);
    EXPECT_EQ(accelerationFactor(AccelerationCurve{}, 0), 1);  // the default is off
}

TEST(TurnAccelerationTest, MeasuresFromThePreviousDetentTheSameWay) {
    TurnAccelerator accelerator(AccelerationCurve{100, 20, 5});
    EXPECT_EQ(accelerator.factorFor(1, 0), 1);                // the first detent
    EXPECT_EQ(accelerator.factorFor(1, 10 * kMs), 5);         // 10 ms later: fast
    EXPECT_DOUBLE_EQ(accelerator.factorFor(1, 70 * kMs), 3);  // 60 ms later
    EXPECT_EQ(accelerator.factorFor(-1, 75 * kMs), 1);        // a reversal starts slow
    EXPECT_EQ(accelerator.factorFor(-1, 80 * kMs), 5);
    EXPECT_EQ(accelerator.factorFor(-1, 380 * kMs), 1);  // a pause
}

}  // namespace
}  // namespace vpe::firmware::knobs
