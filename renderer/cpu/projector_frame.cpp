// SPDX-License-Identifier: MIT
// renderProjectorFrame: for every projector pixel's traced surface (ProjectorPixels), aim for
// the material's radiance, invert the Lambertian screen and the projector's response.
#include "vpe/renderer/cpu/projector_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/proto/viewing_zone.h"
#include "vpe/renderer/cpu/lambertian_screen.h"
#include "vpe/renderer/cpu/parallel_rows.h"
#include "vpe/renderer/cpu/projector_pixels.h"

#include "target_radiance.h"

namespace vpe::renderer {

namespace {

// The target at a point, for the eye the scene's viewing zone gives it (its viewer without one).
std::array<double, 3> zoneTargetRadiance(const RenderScene& scene, const SurfacePoint& point,
                                         const RenderOptions& options) {
    const Vec3d eye =
        proto::zoneEye(point.position, point.geometricNormal,
                       std::span<const std::array<float, 3>>(scene.viewingZone), scene.viewer);
    return targetRadiance(scene, point, eye, options.gain);
}

}  // namespace

ProjectorFrame renderProjectorFrame(const RenderScene& scene, const RenderOptions& options) {
    if (auto problem = checkRenderScene(scene); !problem.empty()) {
        throw std::invalid_argument("renderProjectorFrame: " + problem);
    }
    return renderProjectorFrame(
        scene, ProjectorPixels(scene.mesh, scene.projector, scene.lightShare), options);
}

ProjectorFrame renderProjectorFrame(const RenderScene& scene, const ProjectorPixels& pixels,
                                    const RenderOptions& options) {
    if (auto problem = checkRenderScene(scene); !problem.empty()) {
        throw std::invalid_argument("renderProjectorFrame: " + problem);
    }
    if (!(options.gain > 0) || !std::isfinite(options.gain)) {
        throw std::invalid_argument("renderProjectorFrame: gain must be positive");
    }
    const int width = scene.projector.camera.width, height = scene.projector.camera.height;
    if (scene.measuredLight &&
        (scene.measuredLight->width != width || scene.measuredLight->height != height ||
         scene.measuredLight->irradiance.size() != 3 * static_cast<std::size_t>(width) * height ||
         scene.measuredLight->floor.size() != scene.measuredLight->irradiance.size())) {
        throw std::invalid_argument(
            "renderProjectorFrame: the measured light's maps are not the "
            "projector's size");
    }
    if (pixels.width() != width || pixels.height() != height) {
        throw std::invalid_argument("renderProjectorFrame: the traced pixels are " +
                                    std::to_string(pixels.width()) + "x" +
                                    std::to_string(pixels.height()) + ", the projector " +
                                    std::to_string(width) + "x" + std::to_string(height));
    }

    ProjectorFrame frame;
    frame.level = RgbImage(width, height);
    frame.targetRadiance = RgbImage(width, height);
    frame.coverage = MaskImage(width, height);
    frame.clipped = MaskImage(width, height);
    frame.gainLimit = FloatImage(width, height, std::numeric_limits<float>::infinity());

    forEachRow(height, options.threads, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const std::optional<ProjectorPixel> traced = pixels.trace(x, y);
            if (!traced) {
                continue;
            }
            const std::array<double, 3> target = zoneTargetRadiance(scene, traced->point, options);
            const MeasuredLightMaps* measured = scene.measuredLight.get();
            const std::size_t at = 3 * (static_cast<std::size_t>(y) * width + x);
            CompensatedPixel pixel;
            if (measured != nullptr) {
                // The share divides F: the projector aims for s · (L − D).
                const auto share = static_cast<float>(traced->share);
                const float irradiance[3] = {sharedIrradiance(measured->irradiance[at], share),
                                             sharedIrradiance(measured->irradiance[at + 1], share),
                                             sharedIrradiance(measured->irradiance[at + 2], share)};
                pixel = compensateMeasuredPixel(irradiance, &measured->floor[at],
                                                measured->mixingInverse, measured->inverseResponse,
                                                target, options.gain);
            } else {
                pixel = compensatePixel(scene.surface, scene.projector.response,
                                        traced->compensationScale(), target, options.gain);
            }
            float* level = frame.level.pixel(x, y);
            float* radiance = frame.targetRadiance.pixel(x, y);
            for (std::size_t c = 0; c < 3; ++c) {
                level[c] = static_cast<float>(pixel.level[c]);
                radiance[c] = static_cast<float>(target[c]);
            }
            frame.coverage.at(x, y) = 1;
            frame.clipped.at(x, y) = static_cast<std::uint8_t>(
                (pixel.clippedHigh ? kClippedHigh : 0) | (pixel.clippedLow ? kClippedLow : 0));
            if (std::isfinite(pixel.gainLimit)) {
                // Rounded down: rendering at the stored gain never clips this pixel.
                frame.gainLimit.at(x, y) =
                    std::nextafter(static_cast<float>(pixel.gainLimit), 0.0f);
            }
        }
    });

    // Counted from the masks, serially: rows ran in any order.
    ProjectorFrameStats& stats = frame.stats;
    stats.gain = options.gain;
    for (std::size_t i = 0; i < frame.coverage.values.size(); ++i) {
        if (!frame.coverage.values[i]) {
            continue;
        }
        ++stats.coveredPixels;
        const std::uint8_t flags = frame.clipped.values[i];
        stats.clippedPixels += flags != 0 ? 1 : 0;
        stats.clippedHighPixels += (flags & kClippedHigh) != 0 ? 1 : 0;
        stats.clippedLowPixels += (flags & kClippedLow) != 0 ? 1 : 0;
    }
    stats.clippedFraction = stats.coveredPixels > 0 ? static_cast<double>(stats.clippedPixels) /
                                                          static_cast<double>(stats.coveredPixels)
                                                    : 0.0;
    return frame;
}

double gainForClippedFraction(const ProjectorFrame& frame, double maxClippedFraction) {
    std::vector<float> limits;
    for (std::size_t i = 0; i < frame.coverage.values.size(); ++i) {
        if (frame.coverage.values[i]) {
            limits.push_back(frame.gainLimit.values[i]);
        }
    }
    const double q =
        std::isnan(maxClippedFraction) ? 0.0 : std::clamp(maxClippedFraction, 0.0, 1.0);
    const auto allowed =
        static_cast<std::size_t>(std::floor(q * static_cast<double>(limits.size())));
    if (allowed >= limits.size()) {
        return 1.0;
    }
    // At gain g, the pixels with gainLimit < g clip: at most `allowed` of them at the
    // allowed-th smallest limit, one more at any gain above it.
    std::nth_element(limits.begin(), limits.begin() + static_cast<std::ptrdiff_t>(allowed),
                     limits.end());
    return std::min(1.0, static_cast<double>(limits[allowed]));
}

}  // namespace vpe::renderer
