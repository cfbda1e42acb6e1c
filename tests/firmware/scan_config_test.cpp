// SPDX-License-Identifier: MIT
// The board file's [scan] section: defaults, every key, the scene file resolved against the
// board's folder, and values refused with one line naming file:scan.key.
#include <gtest/gtest.h>

#include "vpe/firmware/board/board_config.h"

#include "thrown_message.h"

namespace vpe::firmware {
namespace {

constexpr const char* kDisplay = "[display]\nbackend = \"headless\"\n";

BoardConfig parse(const std::string& scan, const std::string& source = "boards/x.toml") {
    // Appended, not chained with +: GCC 12 at -O1 (the tests' level, cmake/VpeTests.cmake)
    // warns falsely that operator+ on the temporary overflows (GCC bug 105329's family).
    std::string text = kDisplay;
    text += "[scan]\n";
    text += scan;
    return parseBoardConfig(text, source);
}

std::string refusal(const std::string& scan) {
    return vpe::testing::thrownMessage<BoardConfigError>([&] { parse(scan); }, "");
}

TEST(ScanConfigTest, AbsentSectionMeansNoScan) {
    EXPECT_FALSE(parseBoardConfig(kDisplay, "x.toml").scan.has_value());
}

TEST(ScanConfigTest, Defaults) {
    const BoardConfig board = parse("");
    ASSERT_TRUE(board.scan.has_value());
    const ScanConfig& scan = *board.scan;
    EXPECT_EQ(scan.latencyMs, 150.0);
    EXPECT_FALSE(scan.settleMs.has_value());
    EXPECT_EQ(scan.retries, 3);
    EXPECT_EQ(scan.retryWaitMs, 100.0);
    EXPECT_EQ(scan.exposureUs, 20000);
    EXPECT_EQ(scan.analogueGain, 1.0);
    EXPECT_FALSE(scan.colourGains.has_value());
    EXPECT_EQ(scan.cameraWidth, 1640);
    EXPECT_EQ(scan.cameraHeight, 1232);
    EXPECT_EQ(scan.phasePeriod, 32);
    EXPECT_EQ(scan.phaseSteps, 8);
    EXPECT_EQ(scan.minContrast, 0.05);
    EXPECT_EQ(scan.minLitFraction, 0.005);
    EXPECT_EQ(scan.tolerance, 0.2);
    EXPECT_TRUE(scan.radiometry);
    EXPECT_EQ(scan.radiometryLevels, 16);
    EXPECT_FALSE(scan.simulate.has_value());
    EXPECT_EQ(scan.simulatedLatencyMs, 0.0);
}

TEST(ScanConfigTest, ReadsEveryKey) {
    const BoardConfig board = parse(
        "latency_ms = 80\nsettle_ms = 2500\nretries = 5\nretry_wait_ms = 40\nexposure_us = 30000\n"
        "analogue_gain = 2\ncolour_gains = [1.8, 1.5]\ncamera_size = \"2304x1296\"\n"
        "phase_period = 16\nphase_steps = 4\nmin_contrast = 0.1\nmin_lit_fraction = 0.02\n"
        "tolerance = 0.1\nradiometry = false\nradiometry_levels = 8\n"
        "simulate = \"rehearsal/installation.toml\"\n"
        "simulated_latency_ms = 120\nout = \"scans/latest\"\n",
        "boards/site/board.toml");
    const ScanConfig& scan = *board.scan;
    EXPECT_EQ(scan.latencyMs, 80.0);
    EXPECT_EQ(scan.settleMs, 2500.0);
    EXPECT_EQ(scan.retries, 5);
    EXPECT_EQ(scan.retryWaitMs, 40.0);
    EXPECT_EQ(scan.exposureUs, 30000);
    EXPECT_EQ(scan.analogueGain, 2.0);
    ASSERT_TRUE(scan.colourGains.has_value());
    EXPECT_EQ((*scan.colourGains)[0], 1.8);
    EXPECT_EQ((*scan.colourGains)[1], 1.5);
    EXPECT_EQ(scan.cameraWidth, 2304);
    EXPECT_EQ(scan.cameraHeight, 1296);
    EXPECT_EQ(scan.phasePeriod, 16);
    EXPECT_EQ(scan.phaseSteps, 4);
    EXPECT_EQ(scan.minContrast, 0.1);
    EXPECT_EQ(scan.minLitFraction, 0.02);
    EXPECT_EQ(scan.tolerance, 0.1);
    EXPECT_FALSE(scan.radiometry);
    EXPECT_EQ(scan.radiometryLevels, 8);
    // Relative to the board file's folder.
    EXPECT_EQ(scan.simulate, std::filesystem::path("boards/site/rehearsal/installation.toml"));
    EXPECT_EQ(scan.simulatedLatencyMs, 120.0);
    EXPECT_EQ(scan.out, std::filesystem::path("boards/site/scans/latest"));
    EXPECT_EQ(parse("simulate = \"/srv/x.toml\"\n").scan->simulate,
              std::filesystem::path("/srv/x.toml"));
    EXPECT_EQ(parse("out = \"/var/lib/vpe/scan\"\n").scan->out,
              std::filesystem::path("/var/lib/vpe/scan"));
    EXPECT_FALSE(parse("latency_ms = 1\n").scan->out.has_value());
}

TEST(ScanConfigTest, RefusesWithOneLineNamingTheKey) {
    EXPECT_EQ(refusal("latency = 3\n"),
              "boards/x.toml:scan.latency: unknown key (known: analogue_gain, camera_size, "
              "colour_gains, exposure_us, latency_ms, min_contrast, min_lit_fraction, "
              "out, phase_period, phase_steps, radiometry, radiometry_levels, retries, "
              "retry_wait_ms, settle_ms, simulate, simulated_latency_ms, tolerance)");
    EXPECT_EQ(refusal("out = \"\"\n"),
              "boards/x.toml:scan.out: is empty (the folder the control page's scans are "
              "written to)");
    EXPECT_EQ(refusal("latency_ms = 20000\n"),
              "boards/x.toml:scan.latency_ms: expected a number in [0, 10000], got 20000");
    EXPECT_EQ(refusal("settle_ms = 70000\n"),
              "boards/x.toml:scan.settle_ms: expected a number in [0, 60000], got 70000");
    EXPECT_EQ(refusal("retries = 21\n"),
              "boards/x.toml:scan.retries: expected an integer in 0…20, got 21");
    EXPECT_EQ(refusal("retry_wait_ms = 0\n"),
              "boards/x.toml:scan.retry_wait_ms: expected a number in (0, 10000], got 0");
    EXPECT_EQ(refusal("exposure_us = 0\n"),
              "boards/x.toml:scan.exposure_us: expected an integer in 1…1000000, got 0");
    EXPECT_EQ(refusal("analogue_gain = 0.5\n"),
              "boards/x.toml:scan.analogue_gain: expected a number in [1, 64], got 0.5");
    EXPECT_EQ(refusal("colour_gains = [1, 40]\n"),
              "boards/x.toml:scan.colour_gains: expected [red, blue] gains in (0, 32], got 40");
    EXPECT_EQ(refusal("colour_gains = \"warm\"\n"),
              "boards/x.toml:scan.colour_gains: expected [red, blue] numbers, got a string");
    EXPECT_EQ(refusal("camera_size = \"1640x1232@30\"\n"),
              "boards/x.toml:scan.camera_size: expected \"WxH\" (at most 16384x16384), got "
              "\"1640x1232@30\"");
    EXPECT_EQ(refusal("phase_period = 100\n"),
              "boards/x.toml:scan.phase_period: expected a power of two in 8…1024, got 100");
    EXPECT_EQ(refusal("phase_steps = 65\n"),
              "boards/x.toml:scan.phase_steps: expected an integer in 3…64, got 65");
    EXPECT_EQ(refusal("min_contrast = 0\n"),
              "boards/x.toml:scan.min_contrast: expected a number in (0, 1], got 0");
    EXPECT_EQ(refusal("tolerance = -0.1\n"),
              "boards/x.toml:scan.tolerance: expected a number in [0, 1), got -0.1");
    EXPECT_EQ(refusal("simulate = \"\"\n"),
              "boards/x.toml:scan.simulate: is empty (a scene file such as "
              "\"installation.toml\", relative to this file)");
    EXPECT_EQ(refusal("simulated_latency_ms = 50\n"),
              "boards/x.toml:scan.simulated_latency_ms: only with scan.simulate (a real "
              "projector's latency is its own)");
    EXPECT_EQ(refusal("simulate = \"a.toml\"\nsimulated_latency_ms = -5\n"),
              "boards/x.toml:scan.simulated_latency_ms: expected a number in [0, 10000], got -5");
    EXPECT_EQ(refusal("radiometry = 1\n"),
              "boards/x.toml:scan.radiometry: expected a boolean, got an integer");
    EXPECT_EQ(refusal("radiometry_levels = 65\n"),
              "boards/x.toml:scan.radiometry_levels: expected an integer in 2…64, got 65");
    EXPECT_EQ(refusal("retries = \"3\"\n"),
              "boards/x.toml:scan.retries: expected an integer, got a string");
}

TEST(ScanConfigTest, SectionMustBeATable) {
    try {
        parseBoardConfig("scan = 3\n" + std::string(kDisplay), "x.toml");
        FAIL() << "a scan that is not a table was accepted";
    } catch (const BoardConfigError& error) {
        EXPECT_STREQ(error.what(), "x.toml:scan: expected a table, got an integer");
    }
}

}  // namespace
}  // namespace vpe::firmware
