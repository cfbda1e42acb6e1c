// SPDX-License-Identifier: MIT
// checkRadiometry: how closely the light a bundle's frames put on the true installation matches
// the appearance they aim for, as the installation's camera sees it (docs/radiometry.md) — the test
// of a compensation against what the projector, the plaster and the room really do, not against the
// renderer's own assumptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/vector_types.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::procam {

struct RadiometryCheckOptions {
    std::vector<renderer::Vec3d> lights;  // object frame; empty: four on the visitors' side
    double maxClippedShare = 0.005;       // the gain puts at most this share past the knee
    std::string preset;
    int threads = 0;
};

struct RadiometryView {
    renderer::Vec3d light;
    // RMS over the camera pixels that see the object, away from its outline and from clipped
    // projector pixels, of (seen − scale · target), in levels of 255 of the camera's linear range
    // at the capture's exposure; `scale` the one least-squares factor between them (1 when the
    // bundle's units are the camera's, as measured radiometry's are; free for an assumed one).
    double rmsLevels = 0;
    double scale = 1;
    // Of the projector pixels on the object: those whose target needs more light than the
    // projector has (rolled off), and those darker than the room's light alone makes them.
    double clippedShare = 0, belowFloorShare = 0;
    std::size_t pixels = 0;
    // For people: the camera's view of the projection and the target, linear, scaled alike;
    // and which camera pixels the RMS is over (1).
    renderer::RgbImage seen, target;
    std::vector<std::uint8_t> used;
};

struct RadiometryCheck {
    std::vector<RadiometryView> views;
    double rmsLevels = 0;  // the mean over the lights
    double worstRmsLevels = 0;
    double clippedShare = 0;  // the mean over the lights
    double belowFloorShare = 0;
};

// RMS in levels of 255 of the difference between two checks' camera views of the same
// installation, over the pixels both compared: how much a re-measured bundle changes what the
// camera sees (the stability of a measurement), per light, then the mean.
double viewDifferenceLevels(const RadiometryCheck& a, const RadiometryCheck& b);

// `scene` and `camera` are the true installation (vpe synth-procam's installation.toml): the
// bundle's frames, 8-bit as a projector shows them, are rendered through it without noise.
// Throws InputError when the bundle's projector is not the scene's size.
RadiometryCheck checkRadiometry(const renderer::procam::ProcamScene& scene,
                                const renderer::procam::SimulatedCamera& camera,
                                const proto::BundleView& bundle,
                                const RadiometryCheckOptions& options = {});

}  // namespace vpe::procam
