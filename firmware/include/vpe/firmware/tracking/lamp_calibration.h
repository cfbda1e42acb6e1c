// SPDX-License-Identifier: MIT
// LampCalibration: where the lamp appears in the camera image → where the virtual light is on
// its sphere. Fitted by least squares to points measured by putting the lamp at known light
// directions: 3–5 points give an affine map, 6 or more a full quadratic (which absorbs the
// lens's barrel distortion and the perspective of the room).
#pragma once

#include <array>
#include <span>
#include <stdexcept>

namespace vpe::firmware {

// One measurement: the lamp's image position (pixels) and the light direction it stands for.
struct CalibrationPoint {
    double u = 0.0;
    double v = 0.0;
    double azimuthDeg = 0.0;
    double elevationDeg = 0.0;
};

struct LightDirection {
    double azimuthDeg = 0.0;
    double elevationDeg = 0.0;
};

// A calibration that does not determine a map. One line, without the file: the board-file
// parser prefixes "file:camera.calibration: ".
class CalibrationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class LampCalibration {
public:
    enum class Model { kAffine, kQuadratic };

    // Throws CalibrationError: fewer than 3 points, a non-finite value, or points that leave
    // the map undetermined — on (nearly) one line for the affine map, on (nearly) one conic (a
    // circle, an ellipse, two lines) for the quadratic one. Azimuths are fitted as numbers, so
    // points on either side of ±180° must be written continuously (170 and 190, not −170).
    static LampCalibration fit(std::span<const CalibrationPoint> points);

    LightDirection direction(double u, double v) const;

    Model model() const { return model_; }
    // Root-mean-square distance, in degrees of azimuth and elevation together, between the
    // points' directions and the fitted map's (0 for points on an exact affine/quadratic map).
    double rmsResidualDeg() const { return rmsResidualDeg_; }

private:
    LampCalibration() = default;

    // The monomials [1, s, t, s², st, t²] of the normalized position (s, t): centred on the
    // points' mean and scaled by their RMS radius so the normal equations stay well scaled.
    std::array<double, 6> monomials(double u, double v) const;

    Model model_ = Model::kAffine;
    double centreU_ = 0.0;
    double centreV_ = 0.0;
    double inverseScale_ = 1.0;
    std::array<double, 6> azimuth_{};  // coefficients per monomial (affine: the first 3)
    std::array<double, 6> elevation_{};
    double rmsResidualDeg_ = 0.0;
};

}  // namespace vpe::firmware
