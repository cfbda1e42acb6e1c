// SPDX-License-Identifier: MIT
// The Lambertian screen: forward radiance and its inverse, per channel.
#include "vpe/renderer/cpu/lambertian_screen.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vector_math.h"

namespace vpe::renderer {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

double projectorIrradianceScale(const ProjectorModel& projector, const Vec3d& point,
                                const Vec3d& normal) {
    const Vec3d toProjector = projector.camera.center() - point;
    const double distanceSquared = proto::dot(toProjector, toProjector);
    const double cosine = proto::dot(normal, toProjector) / std::sqrt(distanceSquared);
    return cosine > 0 ? projector.peakIrradiance * cosine / distanceSquared : 0.0;
}

std::array<double, 3> screenRadiance(const ScreenSurface& surface, double irradianceScale,
                                     const std::array<double, 3>& relativeOutput) {
    std::array<double, 3> radiance{};
    for (std::size_t c = 0; c < 3; ++c) {
        radiance[c] = surface.albedo[c] / kPi *
                      (irradianceScale * relativeOutput[c] + surface.ambientIrradiance[c]);
    }
    return radiance;
}

CompensatedPixel compensatePixel(const ScreenSurface& surface,
                                 const proto::ResponseFunction& response, double irradianceScale,
                                 const std::array<double, 3>& target, double gain) {
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    CompensatedPixel pixel;
    pixel.gainLimit = kInfinity;
    for (std::size_t c = 0; c < 3; ++c) {
        const int channel = static_cast<int>(c);
        const double wanted = kPi * target[c] / surface.albedo[c] - surface.ambientIrradiance[c];
        double relative = 0;
        if (irradianceScale > 0) {
            relative = wanted / irradianceScale;
        } else if (wanted != 0) {
            relative = wanted > 0 ? kInfinity : -kInfinity;
        }
        if (relative > 1.0) {
            pixel.level[c] = 1.0;
            pixel.clippedHigh = true;
        } else if (relative < response.blackLevel(channel)) {
            pixel.level[c] = 0.0;
            pixel.clippedLow = true;
        } else {
            pixel.level[c] = response.level(channel, relative);
        }
        if (target[c] > 0) {
            const double limit = gain * surface.albedo[c] *
                                 (irradianceScale + surface.ambientIrradiance[c]) /
                                 (kPi * target[c]);
            pixel.gainLimit = std::min(pixel.gainLimit, limit);
        }
    }
    return pixel;
}

}  // namespace vpe::renderer
