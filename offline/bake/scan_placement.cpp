// SPDX-License-Identifier: MIT
// The installation from a scan folder: calibration, surface, registration or surface mesh.
#include "vpe/bake/scan_placement.h"

#include "vpe/common/input_error.h"
#include "vpe/scan/scan_files.h"

namespace vpe::bake {

proto::PinholeCamera inObjectFrame(const proto::PinholeCamera& device,
                                   const registration::Pose& objectToCamera) {
    // X_device = R_d·(R_o·X + t_o) + T_d.
    proto::PinholeCamera out = device;
    const auto& Rd = device.R;
    const auto& Ro = objectToCamera.R;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double sum = 0;
            for (int k = 0; k < 3; ++k) {
                sum += Rd[static_cast<std::size_t>(3 * i + k)] *
                       Ro[static_cast<std::size_t>(3 * k + j)];
            }
            out.R[static_cast<std::size_t>(3 * i + j)] = sum;
        }
        double moved = device.T[static_cast<std::size_t>(i)];
        for (int k = 0; k < 3; ++k) {
            moved += Rd[static_cast<std::size_t>(3 * i + k)] *
                     objectToCamera.t[static_cast<std::size_t>(k)];
        }
        out.T[static_cast<std::size_t>(i)] = moved;
    }
    return out;
}

ScanPlacement placeFromScan(const std::filesystem::path& scan,
                            const std::optional<scene::ScreenMesh>& mesh,
                            const registration::RegistrationOptions& options) {
    const std::filesystem::path calibrationPath = scan / scan::kCalibrationFile;
    std::error_code error;
    if (!std::filesystem::is_directory(scan, error)) {
        throw InputError(scan, "not a scan folder (vpe scan's --out)");
    }
    const scene::ProjectorCalibration projector = scene::readProjectorCalibration(calibrationPath);
    const std::optional<proto::PinholeCamera> camera =
        scene::readCameraCalibration(calibrationPath);
    if (!camera) {
        throw InputError(calibrationPath, "cam_K: missing (a calibration from vpe calibrate)");
    }
    ScanPlacement placement;
    if (mesh) {
        const scan::ProjectorSurface surface = scan::readSurface(scan / scan::kSurfaceFile);
        if (surface.width != projector.width || surface.height != projector.height) {
            throw InputError(scan / scan::kSurfaceFile, "not the calibration's projector size");
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
    placement.projector = inObjectFrame(projector, placement.objectToCamera);
    placement.camera = inObjectFrame(*camera, placement.objectToCamera);
    return placement;
}

}  // namespace vpe::bake
