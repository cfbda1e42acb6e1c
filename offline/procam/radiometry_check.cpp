// SPDX-License-Identifier: MIT
// The bundle's compensation on the true installation, through its camera (see the header).
#include "vpe/procam/radiometry_check.h"

#include <algorithm>
#include <cmath>

#include "vpe/common/input_error.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/procam/procam_simulator.h"

namespace vpe::procam {

namespace {

namespace sim = renderer::procam;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

RadiometryCheck checkRadiometry(const sim::ProcamScene& scene, const sim::SimulatedCamera& camera,
                                const proto::BundleView& bundle,
                                const RadiometryCheckOptions& options) {
    const proto::PinholeCamera& projector = scene.projector.camera;
    if (static_cast<int>(bundle.projector().width) != projector.width ||
        static_cast<int>(bundle.projector().height) != projector.height) {
        throw common::InputError("the bundle's projector is not the installation's size");
    }
    sim::SimulatedCamera quiet = camera;
    quiet.fullWellElectrons = 0;
    quiet.readNoiseElectrons = 0;
    quiet.monochrome = false;
    const sim::ProcamSimulator simulator(scene, quiet, options.threads);
    const sim::CameraTruth truth = simulator.cameraTruth();
    const renderer::BundleScene bundleScene(bundle, options.preset);
    const renderer::Vec3d viewer = bundleScene.bundleViewer();

    std::vector<renderer::Vec3d> lights = options.lights;
    if (lights.empty()) {
        // On the visitors' side, where the light shows on what they see; from behind, the
        // target is mostly darker than the room already makes the plaster.
        for (const double degrees : {-60.0, -20.0, 20.0, 60.0}) {
            const double a = degrees * kPi / 180;
            lights.push_back({0.5 * std::sin(a), 0.3, 0.2 + 0.5 * std::cos(a)});
        }
    }
    RadiometryCheck check;
    renderer::RenderOptions render;
    render.threads = options.threads;
    const int pw = projector.width, ph = projector.height;
    for (const renderer::Vec3d& light : lights) {
        renderer::VirtualLight virtualLight;
        virtualLight.position = light;
        const renderer::RenderScene renderScene = bundleScene.scene(virtualLight, viewer);
        render.gain = 1;
        render.gain = std::max(1e-6, renderer::gainForClippedFraction(
                                         renderer::renderProjectorFrame(renderScene, render),
                                         options.maxClippedShare));
        const renderer::ProjectorFrame frame = renderer::renderProjectorFrame(renderScene, render);
        // What the projector shows: 8-bit levels.
        renderer::RgbImage shown = frame.level;
        for (float& v : shown.values) {
            v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
        }
        const renderer::RgbImage radiance = simulator.radiance(shown);

        RadiometryView view;
        view.light = light;
        const double covered = std::max<double>(1, double(frame.stats.coveredPixels));
        view.clippedShare = double(frame.stats.clippedHighPixels) / covered;
        view.belowFloorShare = double(frame.stats.clippedLowPixels) / covered;
        view.seen = renderer::RgbImage(radiance.width, radiance.height);
        view.target = renderer::RgbImage(radiance.width, radiance.height);
        // Per camera pixel: the target where its light comes from (bilinear between projector
        // pixels), kept only when the four pixels around it are on the object and unclipped.
        std::vector<std::size_t> used;
        for (std::size_t p = 0; p < radiance.pixelCount(); ++p) {
            const float x = truth.projectorX[p], y = truth.projectorY[p];
            if (std::isnan(x) || std::isnan(truth.pointCamera[3 * p]) || x < 0 || y < 0 ||
                x > float(pw - 1) || y > float(ph - 1)) {
                continue;
            }
            const int x0 = std::min(static_cast<int>(x), pw - 2);
            const int y0 = std::min(static_cast<int>(y), ph - 2);
            const float fx = x - float(x0), fy = y - float(y0);
            bool usable = true;
            float target[3] = {0, 0, 0};
            for (int j = 0; j < 4; ++j) {
                const int px = x0 + (j & 1), py = y0 + (j >> 1);
                usable = usable && frame.coverage.at(px, py) && !frame.clipped.at(px, py);
                const float w = ((j & 1) ? fx : 1 - fx) * ((j >> 1) ? fy : 1 - fy);
                for (std::size_t c = 0; c < 3; ++c) {
                    target[c] += w * frame.targetRadiance.pixel(px, py)[c];
                }
            }
            for (std::size_t c = 0; c < 3; ++c) {
                view.target.values[3 * p + c] = target[c];
                // The camera's linear signal: exposure × radiance (1 = full scale).
                view.seen.values[3 * p + c] =
                    static_cast<float>(camera.exposure * double(radiance.values[3 * p + c]));
            }
            if (usable) {
                used.push_back(p);
            }
        }
        double st = 0, tt = 0;
        for (const std::size_t p : used) {
            for (std::size_t c = 0; c < 3; ++c) {
                st += double(view.seen.values[3 * p + c]) * double(view.target.values[3 * p + c]);
                tt += double(view.target.values[3 * p + c]) * double(view.target.values[3 * p + c]);
            }
        }
        view.scale = tt > 0 ? st / tt : 1.0;
        double squares = 0;
        for (const std::size_t p : used) {
            for (std::size_t c = 0; c < 3; ++c) {
                const double d = double(view.seen.values[3 * p + c]) -
                                 view.scale * double(view.target.values[3 * p + c]);
                squares += d * d;
            }
        }
        view.pixels = used.size();
        view.used.assign(radiance.pixelCount(), 0);
        for (const std::size_t p : used) {
            view.used[p] = 1;
        }
        view.rmsLevels =
            used.empty() ? 0.0 : 255 * std::sqrt(squares / (3.0 * double(used.size())));
        for (float& v : view.target.values) {
            v = static_cast<float>(view.scale * double(v));
        }
        check.views.push_back(std::move(view));
    }
    for (const RadiometryView& view : check.views) {
        check.rmsLevels += view.rmsLevels / double(check.views.size());
        check.clippedShare += view.clippedShare / double(check.views.size());
        check.belowFloorShare += view.belowFloorShare / double(check.views.size());
        check.worstRmsLevels = std::max(check.worstRmsLevels, view.rmsLevels);
    }
    return check;
}

double viewDifferenceLevels(const RadiometryCheck& a, const RadiometryCheck& b) {
    if (a.views.size() != b.views.size() || a.views.empty()) {
        throw common::InputError("two light checks of different lights cannot be compared");
    }
    double total = 0;
    for (std::size_t i = 0; i < a.views.size(); ++i) {
        const RadiometryView& u = a.views[i];
        const RadiometryView& v = b.views[i];
        double squares = 0;
        std::size_t count = 0;
        for (std::size_t p = 0; p < u.used.size() && p < v.used.size(); ++p) {
            if (!u.used[p] || !v.used[p]) {
                continue;
            }
            for (std::size_t c = 0; c < 3; ++c) {
                const double d =
                    double(u.seen.values[3 * p + c]) - double(v.seen.values[3 * p + c]);
                squares += d * d;
            }
            ++count;
        }
        total += count ? 255 * std::sqrt(squares / (3.0 * double(count))) : 0.0;
    }
    return total / double(a.views.size());
}

}  // namespace vpe::procam
