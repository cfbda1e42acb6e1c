// SPDX-License-Identifier: MIT
// BoardConfig: the boards/ files parse; unknown keys, wrong types and malformed values are
// refused with one line naming file:key.
#include "vpe/firmware/board/board_config.h"

#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "test_paths.h"
#include "thrown_message.h"

namespace vpe::firmware {
namespace {

std::string errorOf(const std::string& text) {
    return vpe::testing::thrownMessage<BoardConfigError>(
        [&] { parseBoardConfig(text, "test.toml"); });
}

// Each text refused with exactly its one line.
void expectRefusals(const std::vector<std::pair<std::string, std::string>>& refusals) {
    for (const auto& [text, refusal] : refusals) {
        EXPECT_EQ(errorOf(text), refusal) << text;
    }
}

TEST(BoardConfigTest, ReadsTheRepositoryBoards) {
    const BoardConfig headless =
        loadBoardConfig(std::string(test_paths::sourceDir()) + "/boards/headless.toml");
    EXPECT_EQ(headless.display.backend, DisplayBackend::kHeadless);
    EXPECT_FALSE(headless.render.width.has_value());

    const BoardConfig rpi4 =
        loadBoardConfig(std::string(test_paths::sourceDir()) + "/boards/rpi4.toml");
    EXPECT_EQ(rpi4.display.backend, DisplayBackend::kKms);
    EXPECT_EQ(rpi4.display.device, "/dev/dri/card0");
    EXPECT_EQ(rpi4.display.connector, "auto");
    EXPECT_FALSE(rpi4.display.mode.has_value());
    EXPECT_TRUE(rpi4.display.atomic);

    const BoardConfig rpi5 =
        loadBoardConfig(std::string(test_paths::sourceDir()) + "/boards/rpi5.toml");
    EXPECT_EQ(rpi5.display.device, "/dev/dri/card1");
    EXPECT_EQ(rpi5.display.connector, "HDMI-A-1");
    ASSERT_TRUE(rpi5.display.mode.has_value());
    EXPECT_EQ(rpi5.display.mode->width, 1920);
    EXPECT_EQ(rpi5.display.mode->height, 1080);
    EXPECT_EQ(rpi5.display.mode->refresh, 60);
}

TEST(BoardConfigTest, ParsesSizesAndModes) {
    const BoardConfig config = parseBoardConfig(
        "[display]\nbackend = \"headless\"\n[render]\nsize = \"160x120\"\n", "t.toml");
    EXPECT_EQ(config.render.width, 160);
    EXPECT_EQ(config.render.height, 120);
    EXPECT_FALSE(parseBoardConfig("[display]\nbackend = \"kms\"\nmodeset = \"legacy\"\n", "t.toml")
                     .display.atomic);
    EXPECT_FALSE(parseDisplayMode("1920x").has_value());
    EXPECT_FALSE(parseDisplayMode("0x10").has_value());
    EXPECT_FALSE(parseDisplayMode("10x10@").has_value());
    EXPECT_EQ(parseDisplayMode("1280x720")->refresh, 0);
}

TEST(BoardConfigTest, RefusesBadFilesWithOneLine) {
    EXPECT_EQ(
        errorOf("[display]\nbackend = \"kms\"\nfoo = 1\n"),
        "test.toml:display.foo: unknown key (known: backend, connector, device, mode, modeset)");
    expectRefusals({
        {"[display]\nbackend = 3\n",
         "test.toml:display.backend: expected a string, got an integer"},
        {"[display]\nbackend = \"x11\"\n",
         "test.toml:display.backend: expected \"headless\" or \"kms\", got \"x11\""},
        {"[display]\nbackend = \"kms\"\nmode = \"1080p\"\n",
         "test.toml:display.mode: expected \"WxH@Hz\", \"WxH\" or \"preferred\", got "
         "\"1080p\""},
        {"[render]\nsize = \"160x120\"\n",
         "test.toml:display: missing (a [display] table with backend = \"headless\" or "
         "\"kms\")"},
        {"[display]\nbackend = \"headless\"\n[render]\nsize = \"160x120@60\"\n",
         "test.toml:render.size: expected \"WxH\" or \"projector\", got \"160x120@60\""},
        {"[display]\nbackend = \"kms\"\nmodeset = \"fast\"\n",
         "test.toml:display.modeset: expected \"auto\" or \"legacy\", got \"fast\""},
        {"display = 1\n", "test.toml:display: expected a table, got an integer"},
        {"[displays]\n",
         "test.toml:displays: unknown key (known: board, bus, camera, display, gpio, idle, "
         "light, osc, render, scan)"},
    });
    const std::string headless = "[display]\nbackend = \"headless\"\n";
    expectRefusals({
        {headless + "[render]\nrate = -1\n",
         "test.toml:render.rate: expected frames per second in [0, 1000] (0: unpaced), got "
         "-1.000000"},
        {headless + "[light]\nazimuth = [-200, 10]\n",
         "test.toml:light.azimuth: must lie within [-180, 180]"},
        {headless + "[light]\nelevation = [40, 10]\n",
         "test.toml:light.elevation: low is above high"},
        {headless + "[light]\ndistance = [0, 1]\n",
         "test.toml:light.distance: must be positive (metres from the object's centre)"},
        {headless + "[light]\nsmoothing_s = \"fast\"\n",
         "test.toml:light.smoothing_s: expected a number, got a string"},
    });
    EXPECT_EQ(errorOf(headless + "[light]\ncolour = 1\n")
                  .rfind("test.toml:light.colour: unknown key (known: azimuth, distance,", 0),
              0u);
    EXPECT_EQ(errorOf(headless + "[idle]\nperiod_s = 0\n"),
              "test.toml:idle.period_s: must be positive");
    EXPECT_EQ(errorOf(headless + "[idle]\nenabled = 1\n"),
              "test.toml:idle.enabled: expected a boolean, got an integer");

    EXPECT_EQ(errorOf("[display]\nbackend = \"kms\"\ndevice = \"\"\n")
                  .rfind("test.toml:display.device: is empty", 0),
              0u);
    const std::string syntax = errorOf("[display\n");
    EXPECT_EQ(syntax.rfind("test.toml:1: ", 0), 0u) << syntax;
    EXPECT_EQ(syntax.find('\n'), std::string::npos);
}

TEST(BoardConfigTest, KeepsTheInputSectionsForTheirRooms) {
    const BoardConfig config = parseBoardConfig(
        "[display]\nbackend = \"headless\"\n[gpio]\nchip = \"gpiochip0\"\n[camera]\n", "t.toml");
    EXPECT_EQ(config.display.backend, DisplayBackend::kHeadless);
    EXPECT_EQ(config.source, "t.toml");
    ASSERT_NE(config.section("gpio"), nullptr);
    EXPECT_EQ(config.section("gpio")->get("chip")->value<std::string>(), "gpiochip0");
    EXPECT_NE(config.section("camera"), nullptr);
    EXPECT_EQ(config.section("osc"), nullptr);
}

TEST(BoardConfigTest, ReadsLightAndIdle) {
    const BoardConfig config = parseBoardConfig(
        "[display]\nbackend = \"headless\"\n[render]\nrate = 30\n"
        "[light]\nazimuth = [-90, 90]\nelevation = [0, 80]\ndistance = [0.2, 1.5]\n"
        "initial_azimuth = 10\ninitial_elevation = 20.5\ninitial_distance = 0.6\n"
        "smoothing_s = 0\nintensity = 2\ninverse_square = true\n"
        "[idle]\nenabled = false\nquiet_s = 5\nperiod_s = 10\nazimuth = [-30, 30]\n"
        "elevation = [10, 40]\nhandover_s = 1\n",
        "t.toml");
    EXPECT_EQ(config.render.rate, 30.0);
    EXPECT_EQ(config.light.limits.azimuthDeg, (std::pair{-90.0, 90.0}));
    EXPECT_EQ(config.light.limits.elevationDeg, (std::pair{0.0, 80.0}));
    EXPECT_EQ(config.light.limits.distanceM, (std::pair{0.2, 1.5}));
    EXPECT_EQ(config.light.initialAzimuthDeg, 10.0);
    EXPECT_EQ(config.light.initialElevationDeg, 20.5);
    EXPECT_EQ(config.light.initialDistanceM, 0.6);
    EXPECT_EQ(config.light.smoothingSeconds, 0.0);
    EXPECT_EQ(config.light.intensity, 2.0);
    EXPECT_TRUE(config.light.inverseSquare);
    EXPECT_FALSE(config.idle.enabled);
    EXPECT_EQ(config.idle.quietSeconds, 5.0);
    EXPECT_EQ(config.idle.periodSeconds, 10.0);
    EXPECT_EQ(config.idle.azimuthDeg, (std::pair{-30.0, 30.0}));
    EXPECT_EQ(config.idle.elevationDeg, (std::pair{10.0, 40.0}));
    EXPECT_EQ(config.idle.handoverSeconds, 1.0);
    const BoardConfig defaults = parseBoardConfig("[display]\nbackend = \"headless\"\n", "d");
    EXPECT_EQ(defaults.render.rate, 60.0);
    EXPECT_FALSE(defaults.light.limits.distanceM.has_value());
    EXPECT_TRUE(defaults.idle.enabled);
}

TEST(BoardConfigTest, NamesMissingFiles) {
    try {
        loadBoardConfig("/nonexistent/board.toml");
        FAIL();
    } catch (const BoardConfigError& error) {
        EXPECT_STREQ(error.what(),
                     "/nonexistent/board.toml: cannot read board file (no such file)");
    }
}

}  // namespace
}  // namespace vpe::firmware
