// SPDX-License-Identifier: MIT
// Light rigs.
#include "vpe/synth/light_rigs.h"

#include <cmath>

namespace vpe::synth {

namespace {

constexpr double kRigDistance = 4.0;

proto::Vec3d aroundVase(double azimuthDegrees, double elevationDegrees) {
    const double a = azimuthDegrees * M_PI / 180, e = elevationDegrees * M_PI / 180;
    return {kRigDistance * std::sin(a) * std::cos(e), kRigDistance * std::sin(e),
            kRigDistance * std::cos(a) * std::cos(e)};
}

proto::Vec3d domeDirection(double azimuthDegrees, double elevationDegrees) {
    const double a = azimuthDegrees * M_PI / 180, e = elevationDegrees * M_PI / 180;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

}  // namespace

LightRig paperRig() {
    LightRig rig;
    rig.name = "paper";
    rig.kind = capture::LightKind::kPoint;
    rig.referenceDistance = kRigDistance;
    for (double elevation : {-10.0, 2.0, 14.0, 26.0, 38.0, 50.0}) {
        for (int a = 0; a < 55; ++a) {
            rig.train.push_back(aroundVase(-81.0 + 3.0 * a, elevation));
        }
    }
    // Held out: halfway between rig positions in azimuth, and between heights.
    for (double elevation : {8.0, 20.0, 44.0}) {
        for (int k = 0; k < 7; ++k) {
            rig.test.push_back(aroundVase(-67.5 + 21.0 * k, elevation));
        }
    }
    return rig;
}

LightRig domeRig() {
    LightRig rig;
    rig.name = "dome";
    rig.kind = capture::LightKind::kDirectional;
    for (double elevation : {10.0, 30.0, 50.0, 70.0}) {
        for (int a = 0; a < 12; ++a) {
            rig.train.push_back(domeDirection(
                30.0 * a + (elevation == 30.0 || elevation == 70.0 ? 15 : 0), elevation));
        }
    }
    rig.train.push_back({0, 0, 1});
    for (double elevation : {20.0, 40.0, 60.0, 80.0}) {
        for (int a = 0; a < 5; ++a) {
            rig.test.push_back(domeDirection(72.0 * a + 7.5 + elevation / 4, elevation));
        }
    }
    return rig;
}

}  // namespace vpe::synth
