// SPDX-License-Identifier: MIT
// PinholeCamera: distortion and its inverse, pixel rays, cameraLookingAt's conventions, the
// camera of a bundle's projector.
#include "vpe/proto/pinhole_camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

// A projector lens as calibrations report them: barrel distortion, a little decentering.
PinholeCamera distortedProjector() {
    PinholeCamera camera = cameraLookingAt(1920, 1080, 30.0, {0.1, 0.2, 1.2}, {0, 0.075, 0});
    camera.K[1] = 0.8;  // a little skew, to exercise K⁻¹
    camera.K[2] += 13.0;
    camera.distortion = {-0.12, 0.08, 0.0015, -0.001, -0.02};
    return camera;
}

TEST(PinholeCamera, UndistortionInvertsDistortionEverywhereInTheImage) {
    const PinholeCamera camera = distortedProjector();
    double worst = 0;
    for (int y = -20; y <= camera.height + 20; y += 7) {
        for (int x = -20; x <= camera.width + 20; x += 11) {
            const Vec2d pixel{double(x), double(y)};
            const Vec2d ideal =
                undistortNormalized(camera.distortion, pixelToNormalized(camera, pixel));
            const Vec2d back =
                normalizedToPixel(camera, distortNormalized(camera.distortion, ideal));
            worst = std::max(worst, std::hypot(back.x - pixel.x, back.y - pixel.y));
        }
    }
    EXPECT_LT(worst, 1e-6);  // pixels
}

TEST(PinholeCamera, PixelRaysProjectBackToTheirPixel) {
    const PinholeCamera camera = distortedProjector();
    const Vec3d c = camera.center();
    for (const Vec2d pixel : {Vec2d{0, 0}, Vec2d{1919, 0}, Vec2d{0, 1079}, Vec2d{1919, 1079},
                              Vec2d{960.25, 540.75}, Vec2d{17, 1003}}) {
        const Vec3d d = pixelRayDirection(camera, pixel);
        for (const double t : {0.3, 1.0, 2.5}) {
            const auto back = projectToPixel(camera, {c.x + t * d.x, c.y + t * d.y, c.z + t * d.z});
            ASSERT_TRUE(back.has_value());
            EXPECT_NEAR(back->x, pixel.x, 1e-6);
            EXPECT_NEAR(back->y, pixel.y, 1e-6);
        }
        // t is the camera-frame depth.
        const Vec3d inCamera = camera.toCamera({c.x + 2 * d.x, c.y + 2 * d.y, c.z + 2 * d.z});
        EXPECT_NEAR(inCamera.z, 2.0, 1e-12);
    }
}

TEST(PinholeCamera, LookingAtPutsTheTargetAtTheCentreWithYDown) {
    const PinholeCamera camera = cameraLookingAt(160, 120, 40.0, {0.3, 0.2, 0.9}, {0, 0.1, 0});
    EXPECT_EQ(checkCamera(camera), "");
    const Vec3d c = camera.center();
    EXPECT_NEAR(c.x, 0.3, 1e-12);
    EXPECT_NEAR(c.y, 0.2, 1e-12);
    EXPECT_NEAR(c.z, 0.9, 1e-12);
    const auto centre = projectToPixel(camera, {0, 0.1, 0});
    ASSERT_TRUE(centre.has_value());
    EXPECT_NEAR(centre->x, 79.5, 1e-9);
    EXPECT_NEAR(centre->y, 59.5, 1e-9);
    const auto above = projectToPixel(camera, {0, 0.15, 0});  // world up is image up
    ASSERT_TRUE(above.has_value());
    EXPECT_LT(above->y, 59.5);
    // The vertical field of view: a point at the top edge's angle lands on row −0.5.
    EXPECT_NEAR(camera.K[4], 60.0 / std::tan(20.0 * 3.14159265358979323846 / 180), 1e-9);
    EXPECT_FALSE(projectToPixel(camera, {0.6, 0.3, 1.8}).has_value());  // behind
}

TEST(PinholeCamera, ChecksRefuseBadCameras) {
    PinholeCamera camera = cameraLookingAt(160, 120, 40.0, {0, 0, 1}, {0, 0, 0});
    EXPECT_EQ(checkCamera(camera), "");
    PinholeCamera mirrored = camera;
    mirrored.R[0] = -mirrored.R[0];
    EXPECT_NE(checkCamera(mirrored), "");
    PinholeCamera flat = camera;
    flat.K[0] = 0;
    EXPECT_NE(checkCamera(flat), "");
    EXPECT_THROW(cameraLookingAt(160, 120, 40.0, {0, 1, 0}, {0, 0, 0}), std::invalid_argument);
}

// The bundle names K, R, T intrinsics, rotation, translation; cameraOf is where they meet.
TEST(PinholeCamera, CameraOfABundleProjectorCopiesItsCalibration) {
    const PinholeCamera original = distortedProjector();
    ProjectorCalibration calibration;
    calibration.width = 1920;
    calibration.height = 1080;
    calibration.intrinsics = original.K;
    calibration.distortion = original.distortion;
    calibration.rotation = original.R;
    calibration.translation = original.T;
    const PinholeCamera camera = cameraOf(calibration);
    EXPECT_EQ(camera.width, 1920);
    EXPECT_EQ(camera.height, 1080);
    EXPECT_EQ(camera.K, original.K);
    EXPECT_EQ(camera.distortion, original.distortion);
    EXPECT_EQ(camera.R, original.R);
    EXPECT_EQ(camera.T, original.T);
    EXPECT_EQ(checkCamera(camera), "");
}

}  // namespace
}  // namespace vpe::proto
