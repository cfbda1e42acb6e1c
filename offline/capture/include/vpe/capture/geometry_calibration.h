// SPDX-License-Identifier: MIT
// GeometryCalibration: the two facts an RTI light file cannot state but its images show —
// how wide the camera's field of view is and how near the lights are. RTI captures are
// read as an orthographic camera under directional lights; real rigs (and SynthRTI's
// renders) have a perspective camera and lights at a finite distance, which moves
// highlights and shading across the image in ways no per-pixel BRDF of (θd, θs) can follow.
#pragma once

#include "vpe/capture/capture.h"

namespace vpe {

struct GeometryCalibration {
    double fieldOfViewDegrees = 0;  // horizontal; 0 = orthographic
    double lightDistance = 0;       // in image half-widths from the centre; 0 = directional

    bool isIdentity() const { return fieldOfViewDegrees == 0 && lightDistance == 0; }
};

// True for captures read from a light file: orthographic camera and directional lights, the
// conventions a calibration replaces. Manifests that state their geometry are left alone.
bool acceptsGeometryCalibration(const Capture& capture);

// The capture re-expressed under a calibration: the surface is the plane z = 0 with the
// image spanning x ∈ [−1, 1]; a pinhole camera on the +z axis sees exactly that span, and
// each light sits at lightDistance along its direction, irradiance normalized at that
// distance. An identity calibration returns the capture unchanged.
Capture applyGeometryCalibration(const Capture& capture, const GeometryCalibration& calibration,
                                 int width, int height);

}  // namespace vpe
