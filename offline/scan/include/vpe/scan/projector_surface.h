// SPDX-License-Identifier: MIT
// ProjectorSurface: what a scan measured, per projector pixel — the surface point its light
// falls on, the normal there and how far to trust them — in the camera's frame (the frame of
// the calibration). Made by triangulating the decoded camera image against the projector: the
// decoded camera pixels, joined into triangles, are drawn into the projector's image, so that
// every projector pixel the camera sees gets its own camera position (sub-pixel) and its own
// exact ray.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/structured_light/pattern_decoder.h"

namespace vpe::scan {

// The two devices of a calibration, in the camera's frame: the camera at the origin (R = I,
// T = 0), the projector at R, T (camera → projector), as procam-calibration's files have them.
struct ProcamRig {
    proto::PinholeCamera camera;
    proto::PinholeCamera projector;
};

struct TriangulationOptions {
    // Camera triangles whose edges are longer than this many camera pixels' footprints (the
    // depth divided by the focal length) span a depth discontinuity, not a surface.
    double maxEdgeFootprints = 12;
    // Rays that pass further apart than this (metres) do not meet: a wrong decode, or a
    // calibration that does not belong to the capture.
    double maxRayGap = 0.002;
    // The half-width (projector pixels) of the window the normals are fitted over.
    int normalRadius = 3;
    // Completion: a projector pixel within this many pixels of measured ones, which no camera
    // triangle reached (the last half camera pixel before the camera's silhouette, where one
    // camera pixel spans several projector pixels), takes the depth the measured neighbours'
    // plane gives along its own ray — when the camera sees projector light where that point
    // falls. Its confidence is halved. 0: none.
    int fillRadius = 3;
    // ... and only where the neighbours' distances along their rays fit their plane to this RMS
    // (metres): a smooth patch, not a step or noise.
    double maxFillResidual = 5e-5;
    // Camera pixels placed less precisely than this (σ in projector pixels,
    // DecodedScan::precision) stay out of the surface: a wide Gray bin's rounding, where the
    // phase could not help, is a right code but no surface point. A Gray code down to single
    // pixels (σ = 1/√12) stays in.
    double maxSigma = 1.0;
    // Lit camera pixels (DecodedScan::direct) have at least this much direct light.
    double minDirect = 0.015;
    int threads = 0;
};

struct ProjectorSurface {
    int width = 0, height = 0;            // the projector's
    std::vector<float> position;          // width·height·3, metres, camera frame; NaN unmeasured
    std::vector<float> normal;            // width·height·3, unit, towards the projector
    std::vector<float> confidence;        // width·height in [0, 1]: 1 − σ/(½ px) of the decode
    std::vector<float> rayGap;            // width·height, metres between the two rays
    std::vector<float> cameraU, cameraV;  // width·height: the camera position used
    std::size_t measured = 0;
    std::size_t completed = 0;  // of them, by the completion
};

// Throws InputError when the rig's projector size differs from the scan's or nothing could be
// triangulated.
ProjectorSurface triangulateScan(const structured_light::DecodedScan& scan, const ProcamRig& rig,
                                 const TriangulationOptions& options = {});

// The ray-ray midpoint of origin1 + s·d1 and origin2 + t·d2, and their distance.
struct RayMeeting {
    proto::Vec3d point;
    double gap = 0;
    bool valid = false;  // false for parallel rays
};
RayMeeting closestApproach(const proto::Vec3d& origin1, const proto::Vec3d& direction1,
                           const proto::Vec3d& origin2, const proto::Vec3d& direction2);

}  // namespace vpe::scan
