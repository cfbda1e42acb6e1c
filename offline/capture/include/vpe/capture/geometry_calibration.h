// SPDX-License-Identifier: MIT
// GeometryCalibration: what an RTI light file cannot state but its images show — how wide
// the camera's field of view is, how near the lights are, and how the camera stored
// radiance. RTI captures are read as an orthographic camera under directional lights with
// sRGB JPEGs; real rigs (and SynthRTI's renders) have a perspective camera and lights at a
// finite distance, which moves highlights and shading across the image in ways no per-pixel
// BRDF of (θd, θs) can follow, and many RTI cameras store radiance nearly linearly, which
// sRGB decoding turns into a cos^2.2 falloff that no physical BRDF extrapolates. Nor can it
// state how much light each lamp delivers: domes have lamps of unequal brightness, and parts of
// the rig can block the lowest ones (realrti-dev item7: lights 0–8° above the horizon, over
// 110° of azimuth, reach the object at 0.5–42% of the others).
#pragma once

#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::capture {

// The relative intensity of the light from one direction, as calibrated.
struct LightIntensity {
    Vec3d direction;  // unit, as the capture states it
    double intensity = 1;
};

struct GeometryCalibration {
    double fieldOfViewDegrees = 0;  // horizontal; 0 = orthographic
    double lightDistance = 0;       // in image half-widths from the centre; 0 = directional
    double responseGamma = 0;       // stored = linear^(1/γ); 0 = as the capture states
    // The lights' intensities at the object, per calibrated direction; empty: as stated. A
    // light between them takes lightIntensityAt().
    std::vector<LightIntensity> lightIntensities;

    bool isIdentity() const {
        return fieldOfViewDegrees == 0 && lightDistance == 0 && responseGamma == 0 &&
               lightIntensities.empty();
    }
};

// The intensity of a light from `direction` (unit): a table entry's own when it is one,
// else interpolated between the two nearest entries, inverse to their distance. Distance
// weighs elevation 3× azimuth: what blocks a dome's lights (a rim, a stand, the object's
// mount) cuts them off below an elevation that changes slowly with azimuth, so a light is
// more like its neighbour on the same ring than the one above it.
double lightIntensityAt(const std::vector<LightIntensity>& table, const Vec3d& direction);

// True for captures read from a light file: orthographic camera and directional lights, the
// conventions a calibration replaces. Manifests that state their geometry are left alone.
bool acceptsGeometryCalibration(const Capture& capture);

// True when the capture leaves its images' encoding to the default (light files, manifests
// with "encoding": "auto"): a response may be calibrated for its 8-bit images.
bool acceptsResponseCalibration(const Capture& capture);

// The capture re-expressed under a calibration: the surface is the plane z = 0 with the
// image spanning x ∈ [−1, 1]; a pinhole camera on the +z axis sees exactly that span, and
// each light sits at lightDistance along its direction, irradiance normalized at that
// distance; a response gamma re-encodes the images (ImageEncoding::kGamma). An identity
// calibration returns the capture unchanged.
Capture applyGeometryCalibration(const Capture& capture, const GeometryCalibration& calibration,
                                 int width, int height);

// What a model fitted under `calibration` predicts another capture under: the parts of the
// calibration that capture accepts (a manifest's stated camera, lights or encoding win).
// Applying it to a capture already under it changes nothing.
Capture applyAcceptedCalibration(const Capture& capture, GeometryCalibration calibration, int width,
                                 int height);

}  // namespace vpe::capture
