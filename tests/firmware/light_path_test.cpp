// SPDX-License-Identifier: MIT
// ScriptedLightPath: a circle of the documented radius around the object, on the viewer's side,
// one turn per period.
#include "vpe/firmware/light_path.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

TEST(LightPathTest, CirclesTheObjectOnTheViewersSide) {
    const std::vector<float> box{-0.1f, 0.0f, -0.1f, 0.1f, 0.2f, 0.1f};
    const ScriptedLightPath path(box, {0.0f, 0.1f, 2.0f}, 40);
    EXPECT_NEAR(path.centre()[1], 0.1f, 1e-6f);
    EXPECT_NEAR(path.radius(), 2.0f * std::sqrt(0.03f), 1e-5f);
    for (long frame = 0; frame < 40; ++frame) {
        const auto p = path.position(frame);
        const float dx = p[0] - path.centre()[0], dy = p[1] - path.centre()[1],
                    dz = p[2] - path.centre()[2];
        EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), path.radius(), 1e-5f);
        EXPECT_NEAR(dz, 0.5f * path.radius(), 1e-5f);  // 60° off the axis toward the viewer
    }
    const auto a = path.position(3), b = path.position(43), c = path.position(23);
    EXPECT_FLOAT_EQ(a[0], b[0]);
    EXPECT_NEAR(a[0] - path.centre()[0], -(c[0] - path.centre()[0]), 1e-5f);
}

}  // namespace
}  // namespace vpe::firmware
