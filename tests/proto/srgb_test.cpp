// SPDX-License-Identifier: MIT
// The sRGB transfer function.
#include "vpe/proto/srgb.h"

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

TEST(Srgb, KnownValues) {
    EXPECT_DOUBLE_EQ(srgbToLinear(0.0), 0.0);
    EXPECT_DOUBLE_EQ(srgbToLinear(1.0), 1.0);
    EXPECT_NEAR(srgbToLinear(0.5), 0.2140411, 1e-7);
    EXPECT_NEAR(linearToSrgb(0.18), 0.4613561, 1e-7);
}

TEST(Srgb, RoundTripsEveryEightBitCode) {
    for (int code = 0; code < 256; ++code) {
        const double encoded = code / 255.0;
        EXPECT_NEAR(linearToSrgb(srgbToLinear(encoded)), encoded, 1e-12);
    }
}

TEST(Srgb, ContinuousAtTheLinearSegment) {
    EXPECT_NEAR(srgbToLinear(0.04045 - 1e-12), srgbToLinear(0.04045 + 1e-12), 1e-8);
    // The standard's two segments meet to within 1e-7, not exactly.
    EXPECT_NEAR(linearToSrgb(0.0031308 - 1e-12), linearToSrgb(0.0031308 + 1e-12), 1e-6);
}

}  // namespace
}  // namespace vpe::proto
