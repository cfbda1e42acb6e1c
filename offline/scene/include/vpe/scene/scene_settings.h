// SPDX-License-Identifier: MIT
// SceneSettings: the rest of what `vpe bake` needs to know about the room — where the viewer
// stands, how white the screen object really is, and what light falls on it besides the
// projector's — and the strict parsing of their command-line values.
#pragma once

#include <array>
#include <string_view>

#include "vpe/proto/reflection_geometry.h"

namespace vpe::scene {

struct SceneSettings {
    // The viewer's eye, object frame, metres: by default a metre in front of the demo vase,
    // level with its middle (the demo projector stands on the same side).
    proto::Vec3<double> viewer{0, 0.075, 1.0};
    // Diffuse albedo of the plaster, linear RGB in (0, 1].
    std::array<double, 3> screenAlbedo{0.85, 0.85, 0.85};
    // Radiance the room adds on the screen, in units of the projector's full white on a
    // perfect white screen, linear RGB ≥ 0.
    std::array<double, 3> ambient{0, 0, 0};
};

// "x,y,z": exactly three finite numbers separated by commas (blanks around them allowed).
// Throws InputError "WHAT: 'TEXT' is not x,y,z ..." otherwise.
std::array<double, 3> parseTriple(std::string_view text, std::string_view what);

// A position in metres (parseTriple).
proto::Vec3<double> parsePosition(std::string_view text, std::string_view what);
// An albedo: one grey value or r,g,b, each in (0, 1].
std::array<double, 3> parseAlbedo(std::string_view text, std::string_view what);
// An ambient level: one grey value or r,g,b, each ≥ 0.
std::array<double, 3> parseAmbient(std::string_view text, std::string_view what);
// A camera's black level, share of its range: one value or r,g,b, each in [0, 0.5).
std::array<double, 3> parseBlackLevel(std::string_view text, std::string_view what);

}  // namespace vpe::scene
