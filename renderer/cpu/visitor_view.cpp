// SPDX-License-Identifier: MIT
// simulateVisitorView and renderDirectView: ray cast every viewer pixel, then light the white
// object with the projector pattern, or shade it with the material.
#include "vpe/renderer/cpu/visitor_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "vpe/renderer/cpu/lambertian_screen.h"
#include "vpe/renderer/cpu/parallel_rows.h"
#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/surface_point.h"

#include "target_radiance.h"
#include "vector_math.h"

namespace vpe::renderer {

namespace {

// Calls visit(x, y, point) for every pixel of `camera` whose ray hits the mesh, and marks it
// in `coverage`; rows run on `threads`.
template <typename Visit>
void forEachSeenPoint(const RenderScene& scene, const proto::PinholeCamera& camera,
                      const RayCaster& caster, int threads, MaskImage& coverage,
                      const Visit& visit) {
    const Vec3d eye = camera.center();
    forEachRow(camera.height, threads, [&](int y) {
        for (int x = 0; x < camera.width; ++x) {
            const Vec3d direction = pixelRayDirection(camera, {double(x), double(y)});
            const auto hit = caster.closestHit(eye, direction);
            if (!hit) {
                continue;
            }
            coverage.at(x, y) = 1;
            visit(x, y, surfacePoint(scene.mesh, eye, direction, *hit));
        }
    });
}

// Occluders closer to X than this fraction of the projector's distance do not shadow it: the
// rounding of X itself (≈1e-15 relative) is far below, a real occluder (1 µm at 1 m) above.
constexpr double kShadowTolerance = 1e-6;

void checkViewInputs(const char* what, const RenderScene& scene,
                     const proto::PinholeCamera& camera) {
    if (auto problem = checkRenderScene(scene); !problem.empty()) {
        throw std::invalid_argument(std::string(what) + ": " + problem);
    }
    if (auto problem = checkCamera(camera); !problem.empty()) {
        throw std::invalid_argument(std::string(what) + ": viewer camera: " + problem);
    }
}

// Bilinear interpolation of r(level) at a projector pixel coordinate (pixel centres at
// integers), clamp to edge: light is blended, not drive levels.
std::array<double, 3> interpolatedOutput(const RgbImage& pattern,
                                         const proto::ResponseFunction& response, const Vec2d& p) {
    const auto axis = [](double coordinate, int size, int& i0, int& i1, double& f) {
        const double x = std::clamp(coordinate, 0.0, static_cast<double>(size - 1));
        i0 = static_cast<int>(std::floor(x));
        i1 = std::min(i0 + 1, size - 1);
        f = x - i0;
    };
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    double fx = 0, fy = 0;
    axis(p.x, pattern.width, x0, x1, fx);
    axis(p.y, pattern.height, y0, y1, fy);
    const int xs[4] = {x0, x1, x0, x1};
    const int ys[4] = {y0, y0, y1, y1};
    const double ws[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    std::array<double, 3> output{};
    for (int i = 0; i < 4; ++i) {
        if (ws[i] == 0.0) {
            continue;
        }
        const float* level = pattern.pixel(xs[i], ys[i]);
        for (std::size_t c = 0; c < 3; ++c) {
            output[c] +=
                ws[i] * response.output(static_cast<int>(c), static_cast<double>(level[c]));
        }
    }
    return output;
}

// Bilinear interpolation of a share map at a projector pixel coordinate, clamp to edge.
float interpolatedShare(const FloatImage& share, const Vec2d& p) {
    const double x = std::clamp(p.x, 0.0, static_cast<double>(share.width - 1));
    const double y = std::clamp(p.y, 0.0, static_cast<double>(share.height - 1));
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const int x1 = std::min(x0 + 1, share.width - 1), y1 = std::min(y0 + 1, share.height - 1);
    const double fx = x - x0, fy = y - y0;
    const auto at = [&](int px, int py) { return static_cast<double>(share.at(px, py)); };
    return static_cast<float>((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
                              fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1)));
}

}  // namespace

SimulatedView simulateVisitorView(const RenderScene& scene, const RgbImage& pattern,
                                  const proto::PinholeCamera& viewerCamera,
                                  const RenderOptions& options) {
    checkViewInputs("simulateVisitorView", scene, viewerCamera);
    const proto::PinholeCamera& projector = scene.projector.camera;
    if (pattern.width != projector.width || pattern.height != projector.height ||
        pattern.values.size() != pattern.pixelCount() * 3) {
        throw std::invalid_argument(
            "simulateVisitorView: the pattern is " + std::to_string(pattern.width) + "x" +
            std::to_string(pattern.height) + ", the projector " + std::to_string(projector.width) +
            "x" + std::to_string(projector.height));
    }
    const int width = viewerCamera.width, height = viewerCamera.height;
    const RayCaster caster(scene.mesh);
    const Vec3d projectorCenter = projector.center();
    const std::array<double, 3> unlit = screenRadiance(scene.surface, 0.0, {0, 0, 0});

    SimulatedView view;
    view.radiance = RgbImage(width, height);
    view.coverage = MaskImage(width, height);
    view.lit = MaskImage(width, height);
    view.projectorPixel.assign(2 * view.radiance.pixelCount(),
                               std::numeric_limits<float>::quiet_NaN());

    forEachSeenPoint(
        scene, viewerCamera, caster, options.threads, view.coverage,
        [&](int x, int y, const SurfacePoint& point) {
            std::array<double, 3> radiance = unlit;
            const double scale =
                projectorIrradianceScale(scene.projector, point.position, point.normal);
            const auto pixel = projectToPixel(projector, point.position);
            const bool inImage = pixel && pixel->x >= -0.5 && pixel->x <= projector.width - 0.5 &&
                                 pixel->y >= -0.5 && pixel->y <= projector.height - 0.5;
            if (scale > 0 && inImage &&
                !caster.anyHit(projectorCenter, point.position - projectorCenter, 0.0,
                               1.0 - kShadowTolerance)) {
                radiance =
                    screenRadiance(scene.surface, scale,
                                   interpolatedOutput(pattern, scene.projector.response, *pixel));
                view.lit.at(x, y) = 1;
                const std::size_t i =
                    static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                    static_cast<std::size_t>(x);
                view.projectorPixel[2 * i] = static_cast<float>(pixel->x);
                view.projectorPixel[2 * i + 1] = static_cast<float>(pixel->y);
            }
            float* out = view.radiance.pixel(x, y);
            for (std::size_t c = 0; c < 3; ++c) {
                out[c] = static_cast<float>(radiance[c]);
            }
        });
    return view;
}

SimulatedShowView simulateShowView(const std::vector<const RenderScene*>& scenes,
                                   const std::vector<const RgbImage*>& patterns,
                                   const proto::PinholeCamera& viewerCamera,
                                   const RenderOptions& options) {
    if (scenes.empty() || scenes.size() != patterns.size() || scenes.size() > 32) {
        throw std::invalid_argument("simulateShowView: " + std::to_string(scenes.size()) +
                                    " projectors and " + std::to_string(patterns.size()) +
                                    " patterns (1 to 32, one each)");
    }
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        checkViewInputs("simulateShowView", *scenes[i], viewerCamera);
        const proto::PinholeCamera& projector = scenes[i]->projector.camera;
        if (patterns[i]->width != projector.width || patterns[i]->height != projector.height ||
            patterns[i]->values.size() != patterns[i]->pixelCount() * 3) {
            throw std::invalid_argument("simulateShowView: pattern " + std::to_string(i) +
                                        " is not its projector's size");
        }
        if (scenes[i]->mesh.indices.size() != scenes[0]->mesh.indices.size() ||
            scenes[i]->mesh.positions.size() != scenes[0]->mesh.positions.size()) {
            throw std::invalid_argument("simulateShowView: projector " + std::to_string(i) +
                                        "'s object is not the first's");
        }
    }
    const RenderScene& first = *scenes[0];
    const int width = viewerCamera.width, height = viewerCamera.height;
    const RayCaster caster(first.mesh);
    SimulatedShowView view;
    view.radiance = RgbImage(width, height);
    view.coverage = MaskImage(width, height);
    view.litBy = ScalarImage<std::uint32_t>(width, height);
    view.shares.assign(scenes.size(), FloatImage(width, height));
    forEachSeenPoint(
        first, viewerCamera, caster, options.threads, view.coverage,
        [&](int x, int y, const SurfacePoint& point) {
            std::array<double, 3> irradiance{};  // Σ S_i·r̄_i
            std::uint32_t litBy = 0;
            for (std::size_t i = 0; i < scenes.size(); ++i) {
                const ProjectorModel& model = scenes[i]->projector;
                const proto::PinholeCamera& projector = model.camera;
                const double scale = projectorIrradianceScale(model, point.position, point.normal);
                const auto pixel = projectToPixel(projector, point.position);
                const bool inImage = pixel && pixel->x >= -0.5 &&
                                     pixel->x <= projector.width - 0.5 && pixel->y >= -0.5 &&
                                     pixel->y <= projector.height - 0.5;
                const Vec3d centre = projector.center();
                if (scale > 0 && inImage &&
                    !caster.anyHit(centre, point.position - centre, 0.0, 1.0 - kShadowTolerance)) {
                    const std::array<double, 3> output =
                        interpolatedOutput(*patterns[i], model.response, *pixel);
                    for (std::size_t c = 0; c < 3; ++c) {
                        irradiance[c] += scale * output[c];
                    }
                    litBy |= 1u << i;
                    view.shares[i].at(x, y) =
                        scenes[i]->lightShare ? interpolatedShare(*scenes[i]->lightShare, *pixel)
                                              : 1.0f;
                }
            }
            const std::array<double, 3> radiance = screenRadiance(first.surface, 1.0, irradiance);
            view.litBy.at(x, y) = litBy;
            float* out = view.radiance.pixel(x, y);
            for (std::size_t c = 0; c < 3; ++c) {
                out[c] = static_cast<float>(radiance[c]);
            }
        });
    return view;
}

DirectView renderDirectView(const RenderScene& scene, const proto::PinholeCamera& viewerCamera,
                            const RenderOptions& options) {
    checkViewInputs("renderDirectView", scene, viewerCamera);
    if (!(options.gain > 0) || !std::isfinite(options.gain)) {
        throw std::invalid_argument("renderDirectView: gain must be positive");
    }
    const int width = viewerCamera.width, height = viewerCamera.height;
    const RayCaster caster(scene.mesh);
    const Vec3d eye = viewerCamera.center();

    DirectView view;
    view.radiance = RgbImage(width, height);
    view.coverage = MaskImage(width, height);
    forEachSeenPoint(scene, viewerCamera, caster, options.threads, view.coverage,
                     [&](int x, int y, const SurfacePoint& point) {
                         const std::array<double, 3> radiance =
                             targetRadiance(scene, point, eye, options.gain);
                         float* out = view.radiance.pixel(x, y);
                         for (std::size_t c = 0; c < 3; ++c) {
                             out[c] = static_cast<float>(radiance[c]);
                         }
                     });
    return view;
}

}  // namespace vpe::renderer
