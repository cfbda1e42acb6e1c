// SPDX-License-Identifier: MIT
// CameraLampModel: the lamp's direction where its image ray meets the light's sphere — exact on
// projected points, within 2° through the real tracker on noisy synthetic frames over the
// light's limits (camera outside and inside the sphere), rays that miss, the stream's scaling
// and its aspect-ratio refusal, and the [camera] section's choice between table and camera.
#include "vpe/firmware/tracking/camera_lamp_model.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/tracking/camera_config.h"
#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

#include "lamp_direction_survey.h"

namespace vpe::firmware {
namespace {

using testing::LampSurvey;
using testing::LampSurveySettings;
using testing::steps;

// The object: a box 0.2 × 0.3 × 0.2 m standing on the floor (centre (0, 0.15, 0), bounding
// radius 0.206 m), the viewer on +z: azimuth 0 toward +z, +90° toward +x.
const std::vector<float> kBox{-0.1f, 0.0f, -0.1f, 0.1f, 0.3f, 0.1f};
const std::array<float, 3> kViewer{0.0f, 0.2f, 2.0f};

LightSphere sphere() {
    return LightSphere(kBox, kViewer);
}

// A Pi camera (1640 × 1232, binned) with a wide lens and its barrel distortion, mounted high in
// front of the object, looking down at it.
proto::PinholeCamera ceilingCamera() {
    proto::PinholeCamera camera =
        proto::cameraLookingAt(1640, 1232, 50.0, {0.3, 2.2, 1.3}, {0.0, 0.15, 0.0});
    camera.distortion = {-0.18, 0.06, 0.0008, -0.0005, -0.008};
    camera.K[2] += 6.5;  // a principal point off the centre, as calibrations find
    camera.K[5] -= 4.0;
    return camera;
}

// The lamp held 0.7 m from the object's centre; the ceiling camera is 2.6 m away: outside.
constexpr double kOutsideRadius = 0.7;
// A lamp carried along the gallery's walls, 3 m away, and the camera inside that sphere, near
// the object, with a very wide lens.
constexpr double kInsideRadius = 3.0;
proto::PinholeCamera wideCamera() {
    proto::PinholeCamera camera =
        proto::cameraLookingAt(1640, 1232, 95.0, {0.2, 0.5, 0.6}, {0.0, 1.6, -3.0});
    camera.distortion = {-0.25, 0.07, 0.0, 0.0, -0.01};
    return camera;
}

LampSurveySettings surveySettings() {
    LampSurveySettings settings;
    settings.azimuthsDeg = steps(-180.0, 180.0, 15.0);
    settings.elevationsDeg = steps(-10.0, 80.0, 10.0);
    settings.elevationsDeg.push_back(89.0);
    return settings;
}

double angleBetween(const LightDirection& a, const LightDirection& b) {
    const auto unit = [](const LightDirection& d) {
        const double az = d.azimuthDeg * std::numbers::pi / 180,
                     el = d.elevationDeg * std::numbers::pi / 180;
        return proto::Vec3d{std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)};
    };
    const double c = std::clamp(proto::dot(unit(a), unit(b)), -1.0, 1.0);
    return std::acos(c) * 180 / std::numbers::pi;
}

TEST(CameraLampModelTest, InvertsTheProjectionExactly) {
    // No tracker, no noise: the model's direction for each projected lamp is the lamp's.
    for (const auto& [camera, radius] :
         {std::pair{ceilingCamera(), kOutsideRadius}, std::pair{wideCamera(), kInsideRadius}}) {
        const CameraLampModel model(camera, 320, 240, sphere(), radius);
        int seen = 0;
        double worst = 0, worstGrazing = 0;
        for (const double el : steps(-10.0, 89.0, 3.0)) {
            for (const double az : steps(-180.0, 177.0, 3.0)) {
                const std::array<double, 3> p = sphere().toPosition({az, el, radius});
                const auto pixel = proto::projectToPixel(model.streamCamera(), {p[0], p[1], p[2]});
                const proto::Vec3d eye = camera.center();
                const proto::Vec3d ray{p[0] - eye.x, p[1] - eye.y, p[2] - eye.z};
                const proto::Vec3d normal{p[0] - sphere().centre()[0], p[1] - sphere().centre()[1],
                                          p[2] - sphere().centre()[2]};
                if (!pixel || pixel->x < 0 || pixel->y < 0 || pixel->x > 319 || pixel->y > 239 ||
                    (!model.cameraInsideSphere() && proto::dot(ray, normal) >= 0)) {
                    continue;
                }
                // Where the distortion polynomial has folded over (far outside the wide lens's
                // field) the pixel's ray is not the point's: no model can place it.
                // (And near the fold undistortion converges slowly: only rays it recovers to
                // 1e-9 rad count here.)
                const proto::Vec3d back =
                    proto::normalized(proto::pixelRayDirection(model.streamCamera(), *pixel));
                const proto::Vec3d unit = proto::normalized(ray);
                const proto::Vec3d cross{back.y * unit.z - back.z * unit.y,
                                         back.z * unit.x - back.x * unit.z,
                                         back.x * unit.y - back.y * unit.x};
                if (proto::dot(back, unit) <= 0 || proto::dot(cross, cross) > 1e-18) {
                    continue;
                }
                const std::optional<LightDirection> d = model.direction(pixel->x, pixel->y);
                ASSERT_TRUE(d.has_value()) << az << ", " << el;
                // At the silhouette the ray grazes the sphere, and the intersection moves as
                // the square root of rounding: measured apart.
                const double cosine =
                    std::abs(proto::dot(proto::normalized(ray), proto::normalized(normal)));
                (cosine > 0.1 ? worst : worstGrazing) =
                    std::max(cosine > 0.1 ? worst : worstGrazing, angleBetween(*d, {az, el}));
                ++seen;
            }
        }
        EXPECT_GT(seen, 100);
        EXPECT_LT(worst, 1e-5);
        EXPECT_LT(worstGrazing, 1e-3);
        std::printf("exact: %d positions, worst %.2g° (%.2g° within 6° of the silhouette)\n", seen,
                    worst, worstGrazing);
    }
}

TEST(CameraLampModelTest, ScalesTheIntrinsicsToTheStreamWithPixelCentresAtIntegers) {
    const proto::PinholeCamera camera = ceilingCamera();
    const CameraLampModel model(camera, 320, 240, sphere(), kOutsideRadius);
    const proto::PinholeCamera& stream = model.streamCamera();
    const double sx = 320.0 / 1640, sy = 240.0 / 1232;
    EXPECT_EQ(stream.width, 320);
    EXPECT_EQ(stream.height, 240);
    EXPECT_DOUBLE_EQ(stream.K[0], camera.K[0] * sx);
    EXPECT_DOUBLE_EQ(stream.K[4], camera.K[4] * sy);
    EXPECT_DOUBLE_EQ(stream.K[2], (camera.K[2] + 0.5) * sx - 0.5);
    EXPECT_DOUBLE_EQ(stream.K[5], (camera.K[5] + 0.5) * sy - 0.5);
    EXPECT_EQ(stream.distortion, camera.distortion);
    EXPECT_EQ(stream.R, camera.R);
    EXPECT_EQ(stream.T, camera.T);
    // The image's corner (−½, −½) stays the corner.
    const proto::Vec2d corner =
        proto::normalizedToPixel(stream, proto::pixelToNormalized(camera, {-0.5, -0.5}));
    EXPECT_NEAR(corner.x, -0.5, 1e-12);
    EXPECT_NEAR(corner.y, -0.5, 1e-12);
}

TEST(CameraLampModelTest, RefusesAStreamOfAnotherAspectRatio) {
    proto::PinholeCamera camera = ceilingCamera();
    camera.width = 1920;
    camera.height = 1080;
    try {
        CameraLampModel(camera, 320, 240, sphere(), kOutsideRadius);
        FAIL() << "a 16:9 calibration was scaled to a 4:3 stream";
    } catch (const CalibrationError& error) {
        EXPECT_STREQ(error.what(),
                     "the stream's 320x240 (aspect 1.333) is not the camera calibration's "
                     "1920x1080 (aspect 1.778) scaled: the aspect ratios differ by 25.0% (more "
                     "than 1%: a crop)");
    }
    // 1640 × 1232 to 320 × 240 differs by 0.15%: rounding, accepted.
    EXPECT_NO_THROW(CameraLampModel(ceilingCamera(), 320, 240, sphere(), kOutsideRadius));
    EXPECT_THROW(CameraLampModel(ceilingCamera(), 320, 240, sphere(), 0.0), CalibrationError);
    proto::PinholeCamera flat = ceilingCamera();
    flat.K[4] = 0;
    EXPECT_THROW(CameraLampModel(flat, 320, 240, sphere(), kOutsideRadius), CalibrationError);
}

TEST(CameraLampModelTest, KnowsWhetherTheCameraIsInsideTheSphere) {
    EXPECT_FALSE(
        CameraLampModel(ceilingCamera(), 320, 240, sphere(), kOutsideRadius).cameraInsideSphere());
    EXPECT_TRUE(
        CameraLampModel(wideCamera(), 320, 240, sphere(), kInsideRadius).cameraInsideSphere());
    // The same ceiling camera inside a sphere 3 m across: every pixel meets it, ahead.
    const CameraLampModel inside(ceilingCamera(), 320, 240, sphere(), kInsideRadius);
    EXPECT_TRUE(inside.cameraInsideSphere());
    for (const double u : {0.0, 319.0}) {
        for (const double v : {0.0, 239.0}) {
            const std::optional<LightDirection> d = inside.direction(u, v);
            ASSERT_TRUE(d.has_value());
            // Forward: where the ray leaves the sphere, farther than the camera from the object.
            const std::array<double, 3> p =
                sphere().toPosition({d->azimuthDeg, d->elevationDeg, kInsideRadius});
            const proto::Vec3d x = inside.streamCamera().toCamera({p[0], p[1], p[2]});
            EXPECT_GT(x.z, 0) << u << ", " << v;
        }
    }
}

TEST(CameraLampModelTest, ARayThatMissesTheSphereHasNoDirection) {
    // From 2.6 m the 0.7 m sphere fills the middle of the image; the corners look past it.
    const CameraLampModel model(ceilingCamera(), 320, 240, sphere(), kOutsideRadius);
    EXPECT_FALSE(model.direction(0.0, 0.0).has_value());
    EXPECT_FALSE(model.direction(319.0, 239.0).has_value());
    EXPECT_TRUE(model.direction(160.0, 120.0).has_value());
    // A camera looking away from the sphere: the line meets it, but behind the camera.
    const proto::PinholeCamera away =
        proto::cameraLookingAt(320, 240, 40.0, {0.0, 0.5, 2.0}, {0.0, 0.5, 4.0});
    const CameraLampModel behind(away, 320, 240, sphere(), kOutsideRadius);
    EXPECT_FALSE(behind.cameraInsideSphere());
    EXPECT_FALSE(behind.direction(159.5, 119.5).has_value());

    // Through the tracker: a lamp there is a frame without it, counted, then released.
    LampTrackerSettings settings;
    LampTracker tracker(settings, model);
    std::vector<InputEvent> events;
    const auto frame = [](double x, double y, std::uint32_t seed) {
        SyntheticLampFrame scene;
        scene.seed = seed;
        scene.lamp = SyntheticSpot{x, y, 2.5, 400.0};
        return scene.render();
    };
    tracker.onFrame(frame(160.0, 120.0, 1).view(), 0, events);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_TRUE(std::holds_alternative<AimLight>(events[0].action));
    events.clear();
    for (int i = 1; i <= 20; ++i) {
        tracker.onFrame(frame(12.0, 10.0, static_cast<std::uint32_t>(i + 1)).view(), i * 40'000'000,
                        events);
    }
    EXPECT_EQ(tracker.unmappedFrames(), 20u);
    ASSERT_TRUE(tracker.lastBlob().has_value());  // seen, just not placed
    ASSERT_EQ(events.size(), 1u);                 // released once the hold (0.5 s) ran out
    EXPECT_TRUE(std::holds_alternative<ReleaseLight>(events[0].action));
    EXPECT_EQ(events[0].timestampNs, 500'000'000);
    EXPECT_EQ(tracker.refusals(),
              (std::map<std::string, std::uint64_t>{{"camera.ray_misses_sphere", 20}}));
}

// The survey's positions, all mapped, within `maxDeg` (each one named when not) and the median
// within `medianDeg`; the figures printed.
void expectSurveyWithin(const char* what, const LampSurvey& survey, std::size_t minPositions,
                        double maxDeg, double medianDeg) {
    std::printf("%s: %zu positions seen (%zu not), direction error median %.3f°, max %.3f°\n", what,
                survey.positions.size(), survey.skipped, survey.medianErrorDeg(),
                survey.maxErrorDeg());
    EXPECT_GE(survey.positions.size(), minPositions) << what;
    EXPECT_EQ(survey.unmapped(), 0u) << what;
    EXPECT_LE(survey.maxErrorDeg(), maxDeg) << what;
    EXPECT_LE(survey.medianErrorDeg(), medianDeg) << what;
    double worstIncidence = 0;
    for (const auto& p : survey.positions) {
        worstIncidence = std::max(worstIncidence, p.incidenceDeg);
        if (p.errorDeg && *p.errorDeg > maxDeg) {
            ADD_FAILURE() << what << ": lamp at azimuth " << p.azimuthDeg << "°, elevation "
                          << p.elevationDeg << "° (pixel " << p.u << ", " << p.v << ", incidence "
                          << p.incidenceDeg << "°) tracked " << *p.errorDeg << "° off";
        }
    }
    std::printf("%s: rays up to %.1f° from the sphere's normal\n", what, worstIncidence);
}

TEST(CameraLampModelTest, TracksTheLampWithin2DegreesFromOutsideTheSphere) {
    const CameraLampModel model(ceilingCamera(), 320, 240, sphere(), kOutsideRadius);
    const LampSurvey survey = testing::surveyLampDirections(ceilingCamera(), model, sphere(),
                                                            kOutsideRadius, surveySettings());
    // The goal is 2°; measured: 191 positions, median 0.014°, max 0.83° — the worst where the
    // ray grazes the sphere (up to 89.8° from its normal), where a pixel is a long way along it.
    expectSurveyWithin("outside", survey, 180, 1.0, 0.05);
}

TEST(CameraLampModelTest, TracksTheLampWithin2DegreesFromInsideTheSphere) {
    const CameraLampModel model(wideCamera(), 320, 240, sphere(), kInsideRadius);
    const LampSurvey survey = testing::surveyLampDirections(wideCamera(), model, sphere(),
                                                            kInsideRadius, surveySettings());
    // The goal is 2°; measured: 109 positions, median 0.009°, max 0.027° (every ray meets the
    // sphere head-on from inside: at most 14° from its normal here).
    expectSurveyWithin("inside", survey, 100, 0.1, 0.05);
}

// ---- the [camera] section's choice ----------------------------------------------------------

CameraConfig parseCamera(const std::string& text) {
    const toml::table root = toml::parse(std::string_view(text), std::string_view("board.toml"));
    return parseCameraConfig(*root["camera"].as_table(), "board.toml");
}

std::string mapError(const CameraConfig& config, const std::optional<proto::PinholeCamera>& camera,
                     const LightConfig& light = {}) {
    try {
        lampDirectionMapOf(config, camera, sphere(), light, "board.toml");
    } catch (const BoardConfigError& error) {
        return error.what();
    }
    return "(no error)";
}

TEST(CameraLampModelTest, TheBoardChoosesTheTableOrTheBundlesCamera) {
    const CameraConfig withTable = parseCamera(
        "[camera]\nenabled = true\ncalibration = [[20, 20, -60, 50], [300, 20, 60, 50], "
        "[160, 220, 0, 5]]\n");
    // The table wins when written, whatever the bundle has.
    EXPECT_TRUE(std::holds_alternative<LampCalibration>(
        lampDirectionMapOf(withTable, ceilingCamera(), sphere(), {}, "board.toml")));
    EXPECT_TRUE(std::holds_alternative<LampCalibration>(
        lampDirectionMapOf(withTable, std::nullopt, sphere(), {}, "board.toml")));

    // Without a table, the bundle's camera; the lamp's distance from lamp_distance_m, else the
    // light's initial distance, else twice the object's radius (as the light rig).
    const CameraConfig enabled = parseCamera("[camera]\nenabled = true\n");
    const LampDirectionMap fromCamera =
        lampDirectionMapOf(enabled, ceilingCamera(), sphere(), {}, "board.toml");
    ASSERT_TRUE(std::holds_alternative<CameraLampModel>(fromCamera));
    EXPECT_DOUBLE_EQ(std::get<CameraLampModel>(fromCamera).radiusM(),
                     2.0 * sphere().objectRadius());
    LightConfig light;
    light.initialDistanceM = 1.25;
    EXPECT_DOUBLE_EQ(std::get<CameraLampModel>(
                         lampDirectionMapOf(enabled, ceilingCamera(), sphere(), light, "b.toml"))
                         .radiusM(),
                     1.25);
    const CameraConfig distance = parseCamera("[camera]\nenabled = true\nlamp_distance_m = 0.7\n");
    ASSERT_TRUE(distance.lampDistanceM.has_value());
    EXPECT_DOUBLE_EQ(std::get<CameraLampModel>(
                         lampDirectionMapOf(distance, ceilingCamera(), sphere(), light, "b.toml"))
                         .radiusM(),
                     0.7);
    EXPECT_EQ(describeLampDirectionMap(
                  lampDirectionMapOf(distance, ceilingCamera(), sphere(), light, "b.toml")),
              "the bundle's camera (1640x1232 scaled to 320x240; lamp sphere 0.7 m, the camera "
              "outside it)");

    // Neither: one line naming the key.
    EXPECT_EQ(mapError(enabled, std::nullopt),
              "board.toml:camera.calibration: absent, and the bundle carries no camera (bake it "
              "from a scan or a calibration with cam_K)");
    // A calibration of another aspect ratio names the stream's size.
    proto::PinholeCamera wide = ceilingCamera();
    wide.width = 1920;
    wide.height = 1080;
    EXPECT_EQ(mapError(enabled, wide),
              "board.toml:camera.size: the stream's 320x240 (aspect 1.333) is not the camera "
              "calibration's 1920x1080 (aspect 1.778) scaled: the aspect ratios differ by 25.0% "
              "(more than 1%: a crop)");
}

TEST(CameraLampModelTest, RefusesABadLampDistance) {
    for (const char* value : {"0", "-1", "2000", "\"far\""}) {
        try {
            parseCamera(std::string("[camera]\nlamp_distance_m = ") + value + "\n");
            ADD_FAILURE() << value << " accepted";
        } catch (const BoardConfigError& error) {
            EXPECT_TRUE(
                std::string(error.what()).starts_with("board.toml:camera.lamp_distance_m: "))
                << error.what();
        }
    }
}

}  // namespace
}  // namespace vpe::firmware
