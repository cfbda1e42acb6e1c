// SPDX-License-Identifier: MIT
// placeFromScan: the installation as a scan measured it (vpe scan's folder) — the screen
// object's mesh placed in it by registration, or the scan's own surface when there is no mesh —
// with the projector and the camera of the scan's calibration carried into the object's frame,
// the frame the bundle, the viewer and the light are in.
#pragma once

#include <filesystem>
#include <optional>

#include "vpe/registration/mesh_registration.h"
#include "vpe/registration/surface_mesh.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::bake {

struct ScanPlacement {
    scene::ScreenMesh mesh;                 // object frame
    scene::ProjectorCalibration projector;  // object frame → projector
    proto::PinholeCamera camera;            // object frame → camera
    registration::Pose objectToCamera;
    std::optional<registration::RegistrationResult> registration;  // when a mesh was placed
    std::optional<registration::SurfaceChart> chart;               // when the scan is the mesh
};

// Reads SCAN/calibration.yml and SCAN/surface.exr, and registers `mesh` to the surface, or
// without a mesh reads SCAN/surface-mesh.obj with its frame. Throws InputError naming the file
// or the registration's failure.
ScanPlacement placeFromScan(const std::filesystem::path& scan,
                            const std::optional<scene::ScreenMesh>& mesh,
                            const registration::RegistrationOptions& options = {});

}  // namespace vpe::bake
