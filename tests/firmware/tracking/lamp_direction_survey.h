// SPDX-License-Identifier: MIT
// The lamp-direction survey: the lamp put at a grid of light directions on its sphere, seen by a
// TRUE camera (projected with its distortion into the tracking stream), rendered as synthetic
// spots with noise, tracked by the real LampTracker with a camera MODEL (the bundle's, maybe a
// little wrong), and the direction it reports compared with where the lamp was. Shared by the
// tracking tests and the vpe_lamp_direction figure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "vpe/firmware/light/light_sphere.h"
#include "vpe/firmware/tracking/camera_lamp_model.h"
#include "vpe/proto/pinhole_camera.h"

namespace vpe::firmware::testing {

struct LampSurveySettings {
    // The grid of true light directions, degrees.
    std::vector<double> azimuthsDeg;
    std::vector<double> elevationsDeg;
    int streamWidth = 320, streamHeight = 240;
    // The lamp as SyntheticLampFrame draws it: σ in stream pixels, a saturated core.
    double spotRadiusPx = 2.5;
    double spotPeak = 400.0;
    double noiseSigma = 3.0;
    // Frames per position, 40 ms apart, each with its own noise; the last one's direction counts
    // (the One Euro filter has settled on a still lamp).
    int framesPerPosition = 3;
    std::uint32_t seed = 1;
};

struct LampSurveyPosition {
    double azimuthDeg = 0, elevationDeg = 0;  // where the lamp truly was
    double u = 0, v = 0;                      // its image in the stream, through the true camera
    // The angle between the lamp's true direction and the one tracked (nothing: not mapped, the
    // model's ray missed its sphere).
    std::optional<double> errorDeg;
    // Between the true camera's ray and the sphere's normal at the lamp: 90° is the silhouette,
    // where a pixel moves the point far along the sphere.
    double incidenceDeg = 0;
};

struct LampSurvey {
    std::vector<LampSurveyPosition> positions;  // those the true camera sees (below)
    std::size_t skipped = 0;                    // grid positions it does not see
    std::size_t unmapped() const;
    // Over the mapped positions; 0 when there are none.
    double medianErrorDeg() const;
    double maxErrorDeg() const;
};

// The grid's lamps at `radiusM` from `sphere`'s centre, those the true camera sees: in front of
// it, inside the stream with a margin of three spot radii (a spot cut by the edge pulls its
// centroid), where its distortion is one-to-one (OpenCV's polynomial folds back far outside a
// wide lens's field), and on the side of the sphere facing it (for a camera outside the sphere:
// a lamp behind the silhouette shows where the near side is, and no model can tell them apart).
// `model` tracks them (its stream size must be the settings').
LampSurvey surveyLampDirections(const proto::PinholeCamera& trueCamera,
                                const CameraLampModel& model, const LightSphere& sphere,
                                double radiusM, const LampSurveySettings& settings);

// first, first + step, … up to last (included when on the grid).
std::vector<double> steps(double first, double last, double step);

}  // namespace vpe::firmware::testing
