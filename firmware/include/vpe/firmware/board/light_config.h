// SPDX-License-Identifier: MIT
// The board file's [light] and [idle] sections: where the virtual light may go, how fast it
// follows its inputs, and what it does when nobody is steering (boards/README.md).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

namespace vpe::firmware {

// Angles in degrees, distances in metres, on the sphere of light_sphere.h.
struct LightLimits {
    std::pair<double, double> azimuthDeg{-180.0, 180.0};
    std::pair<double, double> elevationDeg{-10.0, 89.0};
    // Empty: [0.5, 4] × the object's bounding radius (known once the bundle is open).
    std::optional<std::pair<double, double>> distanceM;
};

struct LightConfig {
    LightLimits limits;
    double initialAzimuthDeg = 0.0;
    double initialElevationDeg = 30.0;
    std::optional<double> initialDistanceM;  // empty: 2 × the object's bounding radius
    // Time constant of the exponential approach to the target; 0 = no smoothing.
    double smoothingSeconds = 0.12;
    double intensity = 1.0;
    bool inverseSquare = false;
};

struct IdleConfig {
    bool enabled = true;
    double quietSeconds = 30.0;   // no input for this long → the drift starts
    double periodSeconds = 40.0;  // one loop of the drift's figure of eight
    std::pair<double, double> azimuthDeg{-60.0, 60.0};
    std::pair<double, double> elevationDeg{15.0, 55.0};
    double handoverSeconds = 3.0;  // blend from where the light was into the drift
};

// Parse the sections (either may be absent: nullptr gives the defaults). `source` names the
// file in errors. Throws BoardConfigError "file:light.azimuth: …".
LightConfig parseLightConfig(const toml::table* light, const std::string& source);
IdleConfig parseIdleConfig(const toml::table* idle, const std::string& source);

}  // namespace vpe::firmware
