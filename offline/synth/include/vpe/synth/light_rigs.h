// SPDX-License-Identifier: MIT
// The light rigs `vpe synth` can photograph with: the paper's (point lights at 6 heights ×
// 55 azimuths 3° apart, at a fixed distance, and held-out lights between rig positions) and
// an RTI dome (directional rings, like SynthRTI).
#pragma once

#include <string>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::synth {

struct LightRig {
    std::string name;
    capture::LightKind kind = capture::LightKind::kPoint;
    double referenceDistance = 1.0;   // point lights: irradiance 1 at this distance
    std::vector<proto::Vec3d> train;  // positions (point) or unit directions (directional)
    std::vector<proto::Vec3d> test;   // held out: between the training positions
};

// Azimuth is measured around the vase's (y) axis from the camera direction (+z), elevation
// from the horizontal plane; the lights circle the object at 4 units.
LightRig paperRig();
// Rings at 10/30/50/70/90° around the camera axis (12 lights each, 1 at the zenith); test
// rings at 20/40/60/80° (5 each), azimuths between the training ones.
LightRig domeRig();

}  // namespace vpe::synth
