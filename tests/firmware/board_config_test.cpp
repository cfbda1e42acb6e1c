// SPDX-License-Identifier: MIT
// BoardConfig: the boards/ files parse; unknown keys, wrong types and malformed values are
// refused with one line naming file:key.
#include "vpe/firmware/board_config.h"

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

std::string errorOf(const std::string& text) {
    try {
        parseBoardConfig(text, "test.toml");
    } catch (const BoardConfigError& error) {
        return error.what();
    }
    return "(no error)";
}

TEST(BoardConfigTest, ReadsTheRepositoryBoards) {
    const BoardConfig headless = loadBoardConfig(VPE_SOURCE_DIR "/boards/headless.toml");
    EXPECT_EQ(headless.display.backend, DisplayBackend::kHeadless);
    EXPECT_FALSE(headless.render.width.has_value());

    const BoardConfig rpi4 = loadBoardConfig(VPE_SOURCE_DIR "/boards/rpi4.toml");
    EXPECT_EQ(rpi4.display.backend, DisplayBackend::kKms);
    EXPECT_EQ(rpi4.display.device, "/dev/dri/card0");
    EXPECT_EQ(rpi4.display.connector, "auto");
    EXPECT_FALSE(rpi4.display.mode.has_value());
    EXPECT_TRUE(rpi4.display.atomic);

    const BoardConfig rpi5 = loadBoardConfig(VPE_SOURCE_DIR "/boards/rpi5.toml");
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
    EXPECT_EQ(errorOf("[display]\nbackend = 3\n"),
              "test.toml:display.backend: expected a string, got an integer");
    EXPECT_EQ(errorOf("[display]\nbackend = \"x11\"\n"),
              "test.toml:display.backend: expected \"headless\" or \"kms\", got \"x11\"");
    EXPECT_EQ(errorOf("[display]\nbackend = \"kms\"\nmode = \"1080p\"\n"),
              "test.toml:display.mode: expected \"WxH@Hz\", \"WxH\" or \"preferred\", got "
              "\"1080p\"");
    EXPECT_EQ(errorOf("[render]\nsize = \"160x120\"\n"),
              "test.toml:display: missing (a [display] table with backend = \"headless\" or "
              "\"kms\")");
    EXPECT_EQ(errorOf("[display]\nbackend = \"headless\"\n[render]\nsize = \"160x120@60\"\n"),
              "test.toml:render.size: expected \"WxH\" or \"projector\", got \"160x120@60\"");
    EXPECT_EQ(errorOf("[display]\nbackend = \"kms\"\nmodeset = \"fast\"\n"),
              "test.toml:display.modeset: expected \"auto\" or \"legacy\", got \"fast\"");
    EXPECT_EQ(errorOf("display = 1\n"), "test.toml:display: expected a table, got an integer");
    EXPECT_EQ(errorOf("[displays]\n"),
              "test.toml:displays: unknown key (known: board, camera, display, gpio, light, osc, "
              "render)");
    EXPECT_EQ(errorOf("[display]\nbackend = \"kms\"\ndevice = \"\"\n")
                  .rfind("test.toml:display.device: is empty", 0),
              0u);
    const std::string syntax = errorOf("[display\n");
    EXPECT_EQ(syntax.rfind("test.toml:1: ", 0), 0u) << syntax;
    EXPECT_EQ(syntax.find('\n'), std::string::npos);
}

TEST(BoardConfigTest, AcceptsTheReservedSections) {
    const BoardConfig config = parseBoardConfig(
        "[display]\nbackend = \"headless\"\n[gpio]\nchip = \"gpiochip0\"\n[camera]\n[osc]\n"
        "[light]\n",
        "t.toml");
    EXPECT_EQ(config.display.backend, DisplayBackend::kHeadless);
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
