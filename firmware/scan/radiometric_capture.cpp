// SPDX-License-Identifier: MIT
// captureRadiometry: the flat fields drawn in RGB, captured in colour through the scan's loop,
// and the radiometry folder written.
#include "vpe/firmware/scan/radiometric_capture.h"

#include <algorithm>
#include <array>
#include <system_error>
#include <vector>

#include "vpe/firmware/player/player.h"
#include "vpe/firmware/scan/flat_field_check.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/structured_light.h"

namespace vpe::firmware {

RadiometryReport captureRadiometry(CaptureLoop& loop, const ScanCamera& camera,
                                   const ColourCapture& colour, const RadiometrySettings& settings,
                                   const std::filesystem::path& folder,
                                   const RadiometryObserver& observer) {
    const std::int64_t beginNs = scanClockNs();
    RadiometryReport report;
    report.colour = colour;

    proto::RadiometryManifest manifest;
    manifest.fields.width = settings.projectorWidth;
    manifest.fields.height = settings.projectorHeight;
    manifest.fields.levels = settings.levels;
    manifest.fields.cameraResponse = colour.response;
    const std::vector<proto::FlatField> fields = proto::radiometrySequence(manifest.fields);
    report.fields = fields.size();
    const ScanCameraInfo& info = camera.info();
    manifest.camera.width = info.width;
    manifest.camera.height = info.height;
    manifest.camera.bits = colour.bits;
    manifest.camera.channels = 3;
    manifest.camera.response = colour.response;
    manifest.camera.exposureUs = info.exposureUs;
    manifest.camera.analogueGain = info.analogueGain;
    manifest.camera.source = info.source;
    manifest.createdBy = "vpe-player";
    manifest.images.resize(fields.size());

    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) {
        throw ScanError(folder.string() + ": cannot create the radiometry folder (" +
                        error.message() + ")");
    }

    const int colourMax = (1 << colour.bits) - 1;
    FlatFieldCheck check(fields, settings.check,
                         settings.scanNoiseSigma * colourMax / std::max(1, settings.scanMaxValue));
    std::vector<Shot> shots;
    for (const proto::FlatField& field : fields) {
        shots.push_back({field.name(), 3, CaptureRequest{true, field.exposureScale()}});
    }
    const int width = settings.projectorWidth, height = settings.projectorHeight;
    const auto draw = [&fields, width, height](std::size_t index, std::span<std::uint8_t> codes) {
        // Every row alike: one row, then copies.
        const std::size_t rowBytes = static_cast<std::size_t>(width) * 3;
        for (int x = 0; x < width; ++x) {
            const std::array<std::uint8_t, 3> rgb = fields[index].codes(x, width);
            std::copy(rgb.begin(), rgb.end(), codes.begin() + static_cast<std::ptrdiff_t>(3 * x));
        }
        for (int y = 1; y < height; ++y) {
            std::copy(codes.begin(), codes.begin() + static_cast<std::ptrdiff_t>(rowBytes),
                      codes.begin() + static_cast<std::ptrdiff_t>(y * rowBytes));
        }
    };
    const auto accepted = [&](std::size_t index, const CameraImage& image, int attempts) {
        if (image.channels != 3 || image.maxValue != colourMax || image.width != info.width ||
            image.height != info.height) {
            throw ScanError("scan: " + fields[index].name() + ": the camera delivered a " +
                            std::to_string(image.width) + "x" + std::to_string(image.height) +
                            " image of " + std::to_string(image.channels) + " channels, maxval " +
                            std::to_string(image.maxValue) + "; expected " +
                            std::to_string(info.width) + "x" + std::to_string(info.height) +
                            " RGB, maxval " + std::to_string(colourMax));
        }
        proto::RadiometryImage& entry = manifest.images[index];
        entry.file = proto::radiometryImageName(index, fields[index]);
        entry.pattern = fields[index].name();
        entry.attempts = attempts;
        proto::writePnmAtomically(folder / entry.file, image.width, image.height, 3, image.maxValue,
                                  image.samples);
        if (observer.accepted) {
            observer.accepted(fields[index], image);
        }
    };
    // The projector showed the scan's last pattern: black for as long as it takes to show it.
    loop.showBlack(loop.waitMs());
    report.tally = loop.run(shots, check, draw, accepted);
    manifest.projectorLatencyMs = loop.waitMs();
    proto::writeRadiometryManifest(folder, manifest);
    report.captured = true;
    report.litFraction = check.litFraction();
    report.seconds = static_cast<double>(scanClockNs() - beginNs) / 1e9;
    return report;
}

}  // namespace vpe::firmware
