// SPDX-License-Identifier: MIT
// The installation from a scan folder: calibration, surface, registration or surface mesh.
#include "vpe/bake/scan_placement.h"

#include "vpe/common/input_error.h"
#include "vpe/scan/scan_files.h"

namespace vpe::bake {

ScanPlacement placeFromScan(const std::filesystem::path& scan,
                            const std::optional<scene::ScreenMesh>& mesh,
                            const registration::RegistrationOptions& options) {
    const std::filesystem::path calibrationPath = scan / scan::kCalibrationFile;
    std::error_code error;
    if (!std::filesystem::is_directory(scan, error)) {
        throw common::InputError(scan, "not a scan folder (vpe scan's --out)");
    }
    const scene::ProjectorCalibration projector = scene::readProjectorCalibration(calibrationPath);
    const std::optional<proto::PinholeCamera> camera =
        scene::readCameraCalibration(calibrationPath);
    if (!camera) {
        throw common::InputError(calibrationPath,
                                 "cam_K: missing (a calibration from vpe calibrate)");
    }
    ScanPlacement placement;
    if (mesh) {
        const scan::ProjectorSurface surface = scan::readSurface(scan / scan::kSurfaceFile);
        if (surface.width != projector.width || surface.height != projector.height) {
            throw common::InputError(scan / scan::kSurfaceFile,
                                     "not the calibration's projector size");
        }
        placement.registration = registration::registerMesh(*mesh, surface, projector, options);
        placement.objectToCamera = placement.registration->objectToCamera;
        placement.mesh = *mesh;
    } else {
        registration::SurfaceMesh surface = registration::readSurfaceMesh(scan);
        placement.objectToCamera = surface.objectToCamera;
        placement.chart = surface.chart;
        placement.mesh = std::move(surface.mesh);
    }
    placement.projector = registration::inObjectFrame(projector, placement.objectToCamera);
    placement.camera = registration::inObjectFrame(*camera, placement.objectToCamera);
    return placement;
}

}  // namespace vpe::bake
