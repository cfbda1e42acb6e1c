// SPDX-License-Identifier: MIT
// LibcameraLamp without a camera (this machine, CI): construction fails at once with one line
// of the documented type, and nothing hangs or leaks a CameraManager (a second one in the same
// process would abort libcamera). With a camera present the absent-camera tests SKIP.
#include "vpe/firmware/tracking/libcamera_lamp.h"

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

CameraConfig configFor(const std::string& id) {
    // libcamera logs its version and missing IPA modules at INFO/WARN; the test checks the
    // exception, not libcamera's log (set LIBCAMERA_LOG_LEVELS yourself to see it).
    ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
    CameraConfig config;
    config.enabled = true;
    config.id = id;
    config.calibration = {{20, 20, -60, 50}, {300, 20, 60, 50}, {160, 220, 0, 5}};
    return config;
}

// The exception's message, or "" when a camera was opened.
std::string openError(const CameraConfig& config) {
    try {
        LibcameraLamp lamp(config);
    } catch (const CameraUnavailable& error) {
        return error.what();
    }
    return "";
}

TEST(LibcameraLampTest, NoCameraIsOneLine) {
    const std::string error = openError(configFor("auto"));
    if (error.empty()) {
        GTEST_SKIP() << "a camera is present";
    }
    EXPECT_EQ(error, "camera: no camera found (libcamera lists none)");
    // Again: the first manager was stopped and destroyed, or libcamera would abort here.
    EXPECT_EQ(openError(configFor("auto")), error);
}

TEST(LibcameraLampTest, AbsentIdIsNamed) {
    const std::string error = openError(configFor("vpe-test-no-such-camera"));
    ASSERT_FALSE(error.empty()) << "a camera with the test's made-up id was opened";
    EXPECT_EQ(error.rfind("camera: no camera \"vpe-test-no-such-camera\" (libcamera lists ", 0), 0u)
        << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
}

TEST(LibcameraLampTest, BadCalibrationIsRefusedBeforeTheCamera) {
    CameraConfig config = configFor("auto");
    config.calibration.clear();
    EXPECT_THROW(LibcameraLamp{config}, CalibrationError);
}

}  // namespace
}  // namespace vpe::firmware
