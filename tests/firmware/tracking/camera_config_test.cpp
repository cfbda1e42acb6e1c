// SPDX-License-Identifier: MIT
// parseCameraConfig: a full [camera] section, the defaults, and one-line refusals naming
// file:camera.key for every kind of bad value.
#include "vpe/firmware/tracking/camera_config.h"

#include <string>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

#include "../../support/thrown_message.h"
#include "test_paths.h"

namespace vpe::firmware {
namespace {

CameraConfig parse(const std::string& text) {
    const toml::table root = toml::parse(std::string_view(text), std::string_view("board.toml"));
    return parseCameraConfig(*root["camera"].as_table(), "board.toml");
}

std::string errorOf(const std::string& text) {
    return vpe::testing::thrownMessage<BoardConfigError>([&] { parse(text); });
}

const char* const kCalibration =
    "calibration = [[20, 20, -60, 50], [300, 20, 60, 50], [160, 220, 0, 5]]\n";

TEST(CameraConfigTest, ReadsAFullSection) {
    const CameraConfig config = parse(R"([camera]
enabled = true
id = "/base/soc/i2c0mux/i2c@1/imx219@10"
size = "640x480"
exposure_us = 1500
analogue_gain = 2
threshold = 220
relative_threshold = 0.9
min_area = 6
max_area = 3000
hold_s = 0.75
filter = { min_cutoff = 0.8, beta = 0.02, d_cutoff = 1.5 }
calibration = [
    [40, 40, -60, 50], [320, 40, 0, 55], [600, 40, 60, 50],
    [40, 240, -65, 25], [320, 240, 0, 30], [600, 240, 65, 25],
    [40, 440, -60, 5], [320, 440, 0, 8], [600, 440, 60, 5.5],
]
)");
    EXPECT_TRUE(config.enabled);
    EXPECT_EQ(config.id, "/base/soc/i2c0mux/i2c@1/imx219@10");
    EXPECT_EQ(config.tracking.width, 640);
    EXPECT_EQ(config.tracking.height, 480);
    EXPECT_EQ(config.exposureUs, 1500);
    EXPECT_EQ(config.analogueGain, 2.0);
    EXPECT_EQ(config.tracking.blob.threshold, 220);
    EXPECT_EQ(config.tracking.blob.relativeThreshold, 0.9);
    EXPECT_EQ(config.tracking.blob.minArea, 6);
    EXPECT_EQ(config.tracking.blob.maxArea, 3000);
    EXPECT_EQ(config.tracking.holdSeconds, 0.75);
    EXPECT_EQ(config.tracking.filter.minCutoffHz, 0.8);
    EXPECT_EQ(config.tracking.filter.beta, 0.02);
    EXPECT_EQ(config.tracking.filter.derivativeCutoffHz, 1.5);
    ASSERT_EQ(config.calibration.size(), 9u);
    EXPECT_EQ(config.calibration[8].u, 600.0);
    EXPECT_EQ(config.calibration[8].v, 440.0);
    EXPECT_EQ(config.calibration[8].azimuthDeg, 60.0);
    EXPECT_EQ(config.calibration[8].elevationDeg, 5.5);
}

TEST(CameraConfigTest, ReadsTheRepositoryBoards) {
    for (const char* board : {"headless.toml", "rpi4.toml", "rpi5.toml"}) {
        const std::string path = std::string(test_paths::sourceDir()) + "/boards/" + board;
        const toml::table root = toml::parse_file(path);
        const toml::table* camera = root["camera"].as_table();
        ASSERT_NE(camera, nullptr) << path;
        const CameraConfig config = parseCameraConfig(*camera, path);
        EXPECT_GE(config.calibration.size(), 3u) << path;
        // The calibration determines a map over the whole image.
        EXPECT_NO_THROW(LampCalibration::fit(config.calibration)) << path;
    }
}

TEST(CameraConfigTest, EmptySectionGivesTheDefaults) {
    const CameraConfig config = parse("[camera]\n");
    const CameraConfig defaults;
    EXPECT_FALSE(config.enabled);
    EXPECT_EQ(config.id, "auto");
    EXPECT_EQ(config.tracking.width, 320);
    EXPECT_EQ(config.tracking.height, 240);
    EXPECT_EQ(config.exposureUs, defaults.exposureUs);
    EXPECT_EQ(config.tracking.blob.threshold, defaults.tracking.blob.threshold);
    EXPECT_EQ(config.tracking.blob.maxArea, defaults.tracking.blob.maxArea);
    EXPECT_EQ(config.tracking.holdSeconds, defaults.tracking.holdSeconds);
    EXPECT_TRUE(config.calibration.empty());
    // A small image caps the default max_area at its pixel count.
    EXPECT_EQ(parse("[camera]\nsize = \"40x30\"\n").tracking.blob.maxArea, 1200);
}

TEST(CameraConfigTest, RefusesBadValuesWithOneLine) {
    EXPECT_EQ(errorOf("[camera]\nexposure = 3\n"),
              "board.toml:camera.exposure: unknown key (known: analogue_gain, calibration, "
              "enabled, exposure_us, filter, hold_s, id, lamp_distance_m, max_area, min_area, "
              "relative_threshold, size, threshold)");
    EXPECT_EQ(errorOf("[camera]\nenabled = 1\n"),
              "board.toml:camera.enabled: expected a boolean, got an integer");
    EXPECT_EQ(errorOf("[camera]\nid = \"\"\n"),
              "board.toml:camera.id: is empty (\"auto\" or a libcamera camera id)");
    EXPECT_EQ(errorOf("[camera]\nsize = \"320x240@30\"\n"),
              "board.toml:camera.size: expected \"WxH\" (at most 4096x4096), got \"320x240@30\"");
    EXPECT_EQ(errorOf("[camera]\nthreshold = 256\n"),
              "board.toml:camera.threshold: expected an integer in 1…255, got 256");
    EXPECT_EQ(errorOf("[camera]\nthreshold = 200.5\n"),
              "board.toml:camera.threshold: expected an integer, got a number");
    EXPECT_EQ(errorOf("[camera]\nexposure_us = 0\n"),
              "board.toml:camera.exposure_us: expected an integer in 1…1000000, got 0");
    EXPECT_EQ(errorOf("[camera]\nanalogue_gain = 0.5\n"),
              "board.toml:camera.analogue_gain: expected a number in [1, 64], got 0.5");
    EXPECT_EQ(errorOf("[camera]\nrelative_threshold = 1\n"),
              "board.toml:camera.relative_threshold: expected a number in [0, 1), got 1");
    EXPECT_EQ(errorOf("[camera]\nmin_area = 50\nmax_area = 10\n"),
              "board.toml:camera.min_area: 50 is above max_area 10");
    EXPECT_EQ(errorOf("[camera]\nmax_area = 80000\n"),
              "board.toml:camera.max_area: expected an integer in 1…76800, got 80000");
    EXPECT_EQ(errorOf("[camera]\nhold_s = 0\n"),
              "board.toml:camera.hold_s: expected a number in (0, 3600], got 0");
    EXPECT_EQ(errorOf("[camera]\nfilter = { beta = -1 }\n"),
              "board.toml:camera.filter.beta: expected a number in [0, 1000], got -1");
    EXPECT_EQ(errorOf("[camera]\nfilter = { cutoff = 1 }\n"),
              "board.toml:camera.filter.cutoff: unknown key (known: beta, d_cutoff, min_cutoff)");
    EXPECT_EQ(errorOf("[camera]\nfilter = 3\n"),
              "board.toml:camera.filter: expected a table, got an integer");
}

TEST(CameraConfigTest, RefusesBadCalibrationsWithOneLine) {
    // Enabled without a table is a board for a bundle with a camera: judged once the bundle is
    // open (lampDirectionMapOf, camera_lamp_model_test.cpp).
    EXPECT_EQ(errorOf("[camera]\nenabled = true\n"), "(no error)");
    EXPECT_EQ(errorOf(std::string("[camera]\nenabled = true\n") + kCalibration), "(no error)");
    EXPECT_EQ(errorOf("[camera]\ncalibration = \"none\"\n"),
              "board.toml:camera.calibration: expected an array of [u, v, azimuth_deg, "
              "elevation_deg] points, got a string");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[1, 2, 3, 4], [1, 2, 3]]\n"),
              "board.toml:camera.calibration[1]: expected [u, v, azimuth_deg, elevation_deg], "
              "got an array of 3");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[1, 2, 3, 4], 5]\n"),
              "board.toml:camera.calibration[1]: expected [u, v, azimuth_deg, elevation_deg], "
              "got an integer");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[1, 2, \"a\", 4]]\n"),
              "board.toml:camera.calibration[0]: expected [u, v, azimuth_deg, elevation_deg] "
              "numbers, got a string at position 2");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[320, 2, 3, 4]]\n"),
              "board.toml:camera.calibration[0]: image position (320, 2) is outside the 320x240 "
              "image (camera.size)");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[3, 2, 3, 95]]\n"),
              "board.toml:camera.calibration[0]: elevation 95 is outside [-90, 90]");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[3, 2, 3, 5], [30, 20, 10, 8]]\n"),
              "board.toml:camera.calibration: needs at least 3 points [u, v, azimuth_deg, "
              "elevation_deg], got 2");
    EXPECT_EQ(errorOf("[camera]\ncalibration = [[0, 0, 0, 0], [100, 50, 10, 5], "
                      "[200, 100, 20, 10]]\n"),
              "board.toml:camera.calibration: the 3 points lie on (nearly) one line: an affine "
              "map needs 3 points not in a line");
}

}  // namespace
}  // namespace vpe::firmware
