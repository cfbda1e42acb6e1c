// SPDX-License-Identifier: MIT
// GalleryInstallation: a complete simulated installation to rehearse on and test against — the
// built-in vase standing at a pose nobody told vpe, a projector that is not the demo's (lens
// shift, distortion, a response, a black level, defocus), a camera beside it (a Raspberry Pi
// camera's 1640 × 1232 binned raw mode: linear, 10 bits, shot and read noise), a lit room, and
// the checkerboard poses for the calibration (docs/install.md).
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/renderer/procam/procam_scene.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::procam {

struct GalleryOptions {
    int projectorWidth = 1920, projectorHeight = 1080;
    int cameraWidth = 1640, cameraHeight = 1232;
    int boardPoses = 15;          // 0: no calibration captures
    double cameraOffsetM = 0.21;  // the camera's distance to the projector's left
    double exposure = 0.85;       // the camera's (SimulatedCamera::exposure)
    double roomLight = 0.06;      // the room's irradiance on the object (Room::ambient)
    bool noise = true;
    // Chooses the object's pose (a turn about its axis, a lean, an offset) and the noise.
    std::uint64_t seed = 1;
    bool stains = false;  // non-uniform plaster (greyer foot, stains)
    // The light as a real gallery has it (docs/radiometry.md): plaster stained by ±30 % around its
    // mean albedo, a projector whose curves are no gamma (a toe and a shoulder, different per
    // channel) with crosstalk between its primaries, and the room's light at 2 % of the
    // projector's full white on the object. Implies stains.
    bool realisticLight = false;
    // With realisticLight: plaster of one albedo everywhere (no stains, no greyer foot), the
    // product's normal case, whose floor the geometry alone must split.
    bool uniformPlaster = false;
    // The camera sensor's black level (SimulatedCamera::blackLevel), share of full scale.
    double cameraBlack = 0;
};

struct GalleryInstallation {
    scene::ScreenMesh object;                                // the vase in its own frame
    renderer::procam::ProcamScene objectScene;               // the vase at its pose
    std::vector<renderer::procam::ProcamScene> boardScenes;  // the board at each pose, alone
    renderer::procam::CheckerBoard board;                    // the printed board (its pose unset)
    renderer::procam::SimulatedCamera camera;
    renderer::procam::RigidPose objectPose;  // object frame → room (the truth)
};

// Throws InputError for sizes out of range (8..8192) or 1 or 2 board poses.
GalleryInstallation makeGalleryInstallation(const GalleryOptions& options);

// The ScreenMesh as the simulator's object at `pose`.
renderer::procam::ScreenObject screenObjectOf(const scene::ScreenMesh& mesh,
                                              const renderer::procam::RigidPose& pose);

}  // namespace vpe::procam
