// SPDX-License-Identifier: MIT
// LampCalibration: exact recovery of affine and quadratic maps from their points, the least
// squares' normal equations, and refusal of point sets that leave the map undetermined.
#include "vpe/firmware/tracking/lamp_calibration.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../../support/thrown_message.h"

namespace vpe::firmware {
namespace {

LightDirection affineMap(double u, double v) {
    return {0.28 * u - 0.04 * v - 45.0, 0.02 * u - 0.25 * v + 60.0};
}

// Barrel-like bending and a cross term, as a wide lens looking at a room gives.
LightDirection quadraticMap(double u, double v) {
    return {-40.0 + 0.3 * u - 0.02 * v + 4e-4 * u * u - 3e-4 * u * v + 1e-4 * v * v,
            70.0 + 0.01 * u - 0.3 * v - 2e-4 * u * u + 5e-4 * u * v + 3e-4 * v * v};
}

std::vector<CalibrationPoint> pointsOn(LightDirection (*map)(double, double),
                                       const std::vector<std::pair<double, double>>& positions) {
    std::vector<CalibrationPoint> points;
    for (const auto& [u, v] : positions) {
        const LightDirection d = map(u, v);
        points.push_back({u, v, d.azimuthDeg, d.elevationDeg});
    }
    return points;
}

std::string errorOf(const std::vector<CalibrationPoint>& points) {
    return vpe::testing::thrownMessage<CalibrationError>([&] { LampCalibration::fit(points); });
}

void expectRecovers(const LampCalibration& calibration, LightDirection (*map)(double, double),
                    double tolerance) {
    for (double u = 0.0; u <= 319.0; u += 29.0) {
        for (double v = 0.0; v <= 239.0; v += 23.0) {
            const LightDirection expected = map(u, v);
            const LightDirection actual = calibration.direction(u, v);
            EXPECT_NEAR(actual.azimuthDeg, expected.azimuthDeg, tolerance) << u << ", " << v;
            EXPECT_NEAR(actual.elevationDeg, expected.elevationDeg, tolerance) << u << ", " << v;
        }
    }
}

TEST(LampCalibrationTest, RecoversAnAffineMapFromThreePoints) {
    const LampCalibration calibration =
        LampCalibration::fit(pointsOn(affineMap, {{40.0, 30.0}, {280.0, 60.0}, {150.0, 210.0}}));
    EXPECT_EQ(calibration.model(), LampCalibration::Model::kAffine);
    EXPECT_LT(calibration.rmsResidualDeg(), 1e-10);
    expectRecovers(calibration, affineMap, 1e-9);
}

TEST(LampCalibrationTest, RecoversAnAffineMapFromFivePoints) {
    const LampCalibration calibration = LampCalibration::fit(pointsOn(
        affineMap, {{10.0, 10.0}, {300.0, 20.0}, {160.0, 120.0}, {20.0, 220.0}, {310.0, 230.0}}));
    EXPECT_EQ(calibration.model(), LampCalibration::Model::kAffine);
    expectRecovers(calibration, affineMap, 1e-9);
}

TEST(LampCalibrationTest, RecoversAQuadraticMapFromAGrid) {
    std::vector<std::pair<double, double>> grid;
    for (const double u : {20.0, 160.0, 300.0}) {
        for (const double v : {20.0, 120.0, 220.0}) {
            grid.emplace_back(u, v);
        }
    }
    const LampCalibration calibration = LampCalibration::fit(pointsOn(quadraticMap, grid));
    EXPECT_EQ(calibration.model(), LampCalibration::Model::kQuadratic);
    EXPECT_LT(calibration.rmsResidualDeg(), 1e-9);
    expectRecovers(calibration, quadraticMap, 1e-8);

    // Six points in general position determine it too (the fewest the quadratic takes).
    const LampCalibration six = LampCalibration::fit(pointsOn(quadraticMap, {{20.0, 20.0},
                                                                             {300.0, 20.0},
                                                                             {20.0, 220.0},
                                                                             {160.0, 20.0},
                                                                             {20.0, 120.0},
                                                                             {160.0, 120.0}}));
    EXPECT_EQ(six.model(), LampCalibration::Model::kQuadratic);
    expectRecovers(six, quadraticMap, 1e-7);
}

TEST(LampCalibrationTest, FitsNoisyPointsByLeastSquares) {
    std::vector<CalibrationPoint> points = pointsOn(
        affineMap, {{10.0, 10.0}, {300.0, 20.0}, {160.0, 120.0}, {20.0, 220.0}, {310.0, 230.0}});
    const double errors[] = {0.8, -0.5, 0.3, -0.9, 0.4};
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i].azimuthDeg += errors[i];
        points[i].elevationDeg -= 0.5 * errors[i];
    }
    const LampCalibration calibration = LampCalibration::fit(points);
    EXPECT_GT(calibration.rmsResidualDeg(), 0.1);
    // The normal equations: residuals are orthogonal to every column of the design [1, u, v].
    double sum[3] = {0.0, 0.0, 0.0};
    for (const CalibrationPoint& p : points) {
        const double residual = calibration.direction(p.u, p.v).azimuthDeg - p.azimuthDeg;
        sum[0] += residual;
        sum[1] += residual * p.u;
        sum[2] += residual * p.v;
    }
    EXPECT_NEAR(sum[0], 0.0, 1e-9);
    EXPECT_NEAR(sum[1], 0.0, 1e-6);
    EXPECT_NEAR(sum[2], 0.0, 1e-6);
}

TEST(LampCalibrationTest, RefusesCollinearPoints) {
    const std::string collinear =
        "the 3 points lie on (nearly) one line: an affine map needs 3 points not in a line";
    EXPECT_EQ(errorOf(pointsOn(affineMap, {{0.0, 0.0}, {100.0, 50.0}, {300.0, 150.0}})), collinear);
    // Nearly: a thousandth of a pixel off the line over 300 pixels.
    EXPECT_EQ(errorOf(pointsOn(affineMap, {{0.0, 0.0}, {100.0, 50.001}, {300.0, 150.0}})),
              collinear);
    EXPECT_EQ(errorOf(pointsOn(affineMap,
                               {{10.0, 100.0}, {80.0, 100.0}, {200.0, 100.0}, {310.0, 100.0}})),
              "the 4 points lie on (nearly) one line: an affine map needs 3 points not in a line");
    EXPECT_EQ(errorOf(pointsOn(affineMap, {{5.0, 5.0}, {5.0, 5.0}, {5.0, 5.0}})),
              "all 3 points are at the same image position");
}

TEST(LampCalibrationTest, RefusesQuadraticPointsOnOneConic) {
    // Eight points on a ring around the object: u² + v² is a combination of the others there.
    std::vector<std::pair<double, double>> ring;
    for (int i = 0; i < 8; ++i) {
        const double angle = i * std::numbers::pi / 4.0;
        ring.emplace_back(160.0 + 100.0 * std::cos(angle), 120.0 + 100.0 * std::sin(angle));
    }
    const std::string error = errorOf(pointsOn(quadraticMap, ring));
    EXPECT_EQ(error.rfind("the 8 points lie on (nearly) one conic", 0), 0u) << error;
    // The same ring with its centre: determined.
    ring.emplace_back(160.0, 120.0);
    EXPECT_EQ(errorOf(pointsOn(quadraticMap, ring)), "(no error)");
}

TEST(LampCalibrationTest, RefusesTooFewAndNonFinitePoints) {
    EXPECT_EQ(errorOf(pointsOn(affineMap, {{0.0, 0.0}, {100.0, 50.0}})),
              "needs at least 3 points [u, v, azimuth_deg, elevation_deg], got 2");
    std::vector<CalibrationPoint> points =
        pointsOn(affineMap, {{40.0, 30.0}, {280.0, 60.0}, {150.0, 210.0}});
    points[1].elevationDeg = NAN;
    EXPECT_EQ(errorOf(points), "point 1 has a non-finite value");
}

}  // namespace
}  // namespace vpe::firmware
