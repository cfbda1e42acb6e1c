// SPDX-License-Identifier: MIT
// Writing simulated scan folders and the truth beside them.
#include "vpe/procam/simulated_capture.h"

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/registration/mesh_registration.h"
#include "vpe/scene/projector_calibration.h"

namespace vpe::procam {

void writeSimulatedScan(const renderer::procam::ProcamSimulator& simulator,
                        const std::filesystem::path& folder, const SimulatedScanOptions& options,
                        common::ProgressBar* progress) {
    const proto::PinholeCamera& projector = simulator.scene().projector.camera;
    proto::StructuredLightParameters parameters;
    parameters.width = projector.width;
    parameters.height = projector.height;
    parameters.phasePeriod = options.phasePeriod;
    parameters.phaseSteps = options.phaseSteps;
    const proto::StructuredLightSequence sequence(parameters);
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) {
        throw common::InputError(folder, "cannot create the scan folder (" + error.message() + ")");
    }
    const renderer::procam::SimulatedCamera& camera = simulator.camera();
    proto::ScanManifest manifest;
    manifest.patterns = parameters;
    manifest.camera.width = camera.camera.width;
    manifest.camera.height = camera.camera.height;
    manifest.camera.bits = camera.bits;
    manifest.camera.source = options.source;
    manifest.createdBy = "vpe synth-procam";
    std::vector<std::uint8_t> codes(static_cast<std::size_t>(parameters.width) * parameters.height);
    const std::vector<proto::PatternSpec>& patterns = sequence.patterns();
    for (std::size_t i = 0; i < patterns.size(); ++i) {
        sequence.render(patterns[i], codes);
        const renderer::procam::CameraFrame frame = simulator.expose(
            simulator.radiance(codes, options.firstFrame + i), options.firstFrame + i);
        const std::string name = proto::scanImageName(i, patterns[i]);
        try {
            proto::writePnmAtomically(folder / name, frame.width, frame.height, frame.channels,
                                      frame.maxValue(), frame.samples);
        } catch (const std::exception& failure) {
            throw common::InputError(failure.what());
        }
        manifest.images.push_back({name, patterns[i].name(), 1});
        if (progress != nullptr) {
            progress->advance();
        }
    }
    try {
        proto::writeScanManifest(folder, manifest);
    } catch (const std::exception& failure) {
        throw common::InputError(failure.what());
    }
}

void writeSimulatedRadiometry(const renderer::procam::ProcamSimulator& simulator,
                              const std::filesystem::path& folder,
                              const SimulatedRadiometryOptions& options,
                              common::ProgressBar* progress) {
    const proto::PinholeCamera& projector = simulator.scene().projector.camera;
    renderer::procam::SimulatedCamera sensor = simulator.camera();
    sensor.monochrome = false;
    const bool linear = sensor.response == renderer::procam::CameraResponse::kLinear;
    if (!linear) {
        sensor.bits = 8;
    }
    proto::RadiometryManifest manifest;
    manifest.fields.width = projector.width;
    manifest.fields.height = projector.height;
    manifest.fields.levels = options.levels;
    manifest.fields.cameraResponse =
        linear ? proto::CameraResponseKind::kLinear : proto::CameraResponseKind::kUnknown;
    manifest.camera.width = sensor.camera.width;
    manifest.camera.height = sensor.camera.height;
    manifest.camera.bits = sensor.bits;
    manifest.camera.channels = 3;
    manifest.camera.response = manifest.fields.cameraResponse;
    manifest.camera.source = options.source;
    manifest.createdBy = "vpe synth-procam";
    const std::vector<proto::FlatField> fields = proto::radiometrySequence(manifest.fields);
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) {
        throw common::InputError(folder,
                                 "cannot create the radiometry folder (" + error.message() + ")");
    }
    renderer::RgbImage levels(projector.width, projector.height);
    for (std::size_t i = 0; i < fields.size(); ++i) {
        for (int y = 0; y < projector.height; ++y) {
            for (int x = 0; x < projector.width; ++x) {
                const std::array<std::uint8_t, 3> codes = fields[i].codes(x, projector.width);
                for (std::size_t c = 0; c < 3; ++c) {
                    levels.pixel(x, y)[c] = static_cast<float>(codes[c]) / 255.0f;
                }
            }
        }
        renderer::procam::SimulatedCamera exposed = sensor;
        exposed.exposure = sensor.exposure * fields[i].exposureScale();
        const renderer::procam::CameraFrame frame = simulator.expose(
            simulator.radiance(levels, options.firstFrame + i), options.firstFrame + i, exposed);
        const std::string name = proto::radiometryImageName(i, fields[i]);
        try {
            proto::writePnmAtomically(folder / name, frame.width, frame.height, frame.channels,
                                      frame.maxValue(), frame.samples);
        } catch (const std::exception& failure) {
            throw common::InputError(failure.what());
        }
        manifest.images.push_back({name, fields[i].name(), 1});
        if (progress != nullptr) {
            progress->advance();
        }
    }
    try {
        proto::writeRadiometryManifest(folder, manifest);
    } catch (const std::exception& failure) {
        throw common::InputError(failure.what());
    }
}

void writeSimulationTruth(const renderer::procam::ProcamSimulator& simulator,
                          const std::filesystem::path& folder) {
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    const renderer::procam::CameraTruth camera = simulator.cameraTruth();
    const proto::PinholeCamera& c = simulator.camera().camera;
    const std::size_t cameraPixels = static_cast<std::size_t>(c.width) * c.height;
    std::vector<float> cameraValues(cameraPixels * 7);
    for (std::size_t p = 0; p < cameraPixels; ++p) {
        cameraValues[7 * p] = camera.projectorX[p];
        cameraValues[7 * p + 1] = camera.projectorY[p];
        cameraValues[7 * p + 2] = camera.centreX[p];
        cameraValues[7 * p + 3] = camera.centreY[p];
        for (std::size_t k = 0; k < 3; ++k) {
            cameraValues[7 * p + 4 + k] = camera.pointCamera[3 * p + k];
        }
    }
    image::writeImage(
        folder / "camera-truth.exr", c.width, c.height, 7, cameraValues, image::PixelFormat::kFloat,
        {"projector.x", "projector.y", "centre.x", "centre.y", "point.X", "point.Y", "point.Z"});
    const renderer::procam::ProjectorTruth projector = simulator.projectorTruth();
    const std::size_t projectorPixels =
        static_cast<std::size_t>(projector.width) * projector.height;
    std::vector<float> projectorValues(projectorPixels * 7);
    for (std::size_t p = 0; p < projectorPixels; ++p) {
        for (std::size_t k = 0; k < 3; ++k) {
            projectorValues[7 * p + k] = projector.position[3 * p + k];
            projectorValues[7 * p + 3 + k] = projector.normal[3 * p + k];
        }
        projectorValues[7 * p + 6] = projector.seen[p];
    }
    image::writeImage(
        folder / "projector-truth.exr", projector.width, projector.height, 7, projectorValues,
        image::PixelFormat::kFloat,
        {"position.X", "position.Y", "position.Z", "normal.X", "normal.Y", "normal.Z", "seen"});
    // The true calibration in vpe calibrate's own file, in the camera's frame: scans can be
    // decoded with it alone.
    const registration::Pose cameraToRoom = registration::inverse(registration::poseOfDevice(c));
    proto::PinholeCamera cameraAtOrigin = c;
    cameraAtOrigin.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    cameraAtOrigin.T = {0, 0, 0};
    scene::writeProcamCalibration(
        registration::inObjectFrame(simulator.scene().projector.camera, cameraToRoom),
        cameraAtOrigin, std::nullopt, folder / "calibration.yml");
}

}  // namespace vpe::procam
