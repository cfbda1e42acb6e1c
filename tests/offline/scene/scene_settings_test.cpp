// SPDX-License-Identifier: MIT
// Scene settings of `vpe bake`: the demo defaults and strict parsing of triples, albedo and
// ambient.
#include "vpe/scene/scene_settings.h"

#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"

#include "offline/scene/scene_test_support.h"
#include "support/test_data.h"

namespace vpe::scene {
namespace {

using namespace test;  // NOLINT: the shared helpers of scene_test_support.h
using testing::TemporaryFolder;

TEST(SceneSettings, DefaultsAreTheDemos) {
    const SceneSettings settings;
    EXPECT_EQ(settings.screenAlbedo, (std::array<double, 3>{0.85, 0.85, 0.85}));
    EXPECT_EQ(settings.ambient, (std::array<double, 3>{0, 0, 0}));
    EXPECT_DOUBLE_EQ(settings.viewer.z, 1.0);
}

TEST(SceneSettings, ParsesTriplesStrictly) {
    const auto p = parsePosition(" 0.1, -2 ,3e-1", "--viewer");
    EXPECT_DOUBLE_EQ(p.x, 0.1);
    EXPECT_DOUBLE_EQ(p.y, -2);
    EXPECT_DOUBLE_EQ(p.z, 0.3);
    for (const char* bad : {"1,2", "1,2,3,4", "1,,3", "a,b,c", "1,2,nan", "", "1 2 3", "1,2,3,",
                            "1,2,inf", "+-1,2,3", "0x1,2,3"}) {
        SCOPED_TRACE(bad);
        EXPECT_INPUT_ERROR(parseTriple(bad, "--viewer"),
                           "--viewer: '" + std::string(bad) +
                               "' is not x,y,z (three finite numbers separated by commas)");
    }
}

TEST(SceneSettings, ParsesAlbedoAndAmbient) {
    EXPECT_EQ(parseAlbedo("0.8", "--albedo"), (std::array<double, 3>{0.8, 0.8, 0.8}));
    EXPECT_EQ(parseAlbedo("0.9,0.8,0.7", "--albedo"), (std::array<double, 3>{0.9, 0.8, 0.7}));
    EXPECT_INPUT_ERROR(parseAlbedo("1.2", "--albedo"),
                       "--albedo: '1.2': each value must be in (0, 1]");
    EXPECT_INPUT_ERROR(parseAlbedo("0,0.5,0.5", "--albedo"), "each value must be in (0, 1]");
    EXPECT_INPUT_ERROR(parseAlbedo("0.5,0.5", "--albedo"),
                       "--albedo: '0.5,0.5' is not a value or r,g,b");
    EXPECT_EQ(parseAmbient("0.02,0.03,0.04", "--ambient"),
              (std::array<double, 3>{0.02, 0.03, 0.04}));
    EXPECT_INPUT_ERROR(parseAmbient("-0.1", "--ambient"),
                       "--ambient: '-0.1': each value must be ≥ 0");
    EXPECT_EQ(parseBlackLevel("0.004", "--camera-black"),
              (std::array<double, 3>{0.004, 0.004, 0.004}));
    EXPECT_INPUT_ERROR(parseBlackLevel("0.7", "--camera-black"),
                       "--camera-black: '0.7': each value must be in [0, 0.5)");
}

}  // namespace
}  // namespace vpe::scene
