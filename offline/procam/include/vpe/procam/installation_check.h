// SPDX-License-Identifier: MIT
// checkInstallation: a bundle baked from vpe's own measurements (calibrate → scan → bake --scan)
// against the simulated installation it was measured on — what a visitor would see of the
// frames it renders, shown by the true projector on the true object, next to the frames the
// same bundle renders with the true geometry; where its texture lands on the object; and how far
// its pose is from the truth.
#pragma once

#include <filesystem>
#include <vector>

#include "vpe/image/image_metrics.h"
#include "vpe/proto/bundle.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/vector_types.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::procam {

struct InstallationCheckOptions {
    // Virtual lights (object frame, metres); empty: four around the object.
    std::vector<renderer::Vec3d> lights;
    int viewWidth = 480, viewHeight = 360;
    double viewFovDeg = 20;
    std::string preset;  // empty: the bundle's first
    int threads = 0;
};

struct VisitorComparison {
    renderer::Vec3d light;
    double psnr = 0;                   // as people see it: 8-bit sRGB, one exposure for both
    image::Rgb8Image measured, truth;  // what the visitor sees
};

struct InstallationCheck {
    // The bundle's pose of the object against the truth (with the same rule for a turn the
    // geometry leaves free), and where its texture lands on the true object.
    double poseErrorMm = 0, poseErrorDeg = 0;
    bool turnFree = false;
    double misregistrationRmsMm = 0, misregistrationP95Mm = 0, misregistrationMaxMm = 0;
    std::size_t misregistrationPoints = 0;
    std::vector<VisitorComparison> views;
    double psnrMean = 0, psnrMin = 0;
    // The installation's true camera in the object's frame (the truth's, turned as above): what
    // the bundle's camera should have been, for the tracked lamp's error (vpe_lamp_direction).
    proto::PinholeCamera trueCamera;
};

// `scene` is the true installation (its room frame; scene.object at its true pose) and `camera`
// its camera (room frame): what vpe synth-procam's installation.toml holds. The bundle must carry
// the camera (its pose is the measured one) and the object's own mesh. Throws InputError for a
// bundle without a camera, with another mesh, or whose projector is not the scene's size.
InstallationCheck checkInstallation(const renderer::procam::ProcamScene& scene,
                                    const proto::PinholeCamera& camera,
                                    const proto::BundleView& bundle,
                                    const InstallationCheckOptions& options = {});

}  // namespace vpe::procam
