// SPDX-License-Identifier: MIT
// Radiance steps across the u seam of a rendered frame.
#include "support/frame_seam.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/projector_pixels.h"

namespace vpe::testing {

double FrameSeamSteps::mean(const std::vector<double>& steps) {
    double sum = 0;
    for (double x : steps) {
        sum += x;
    }
    return steps.empty() ? 0.0 : sum / static_cast<double>(steps.size());
}

double FrameSeamSteps::quantile(std::vector<double> steps, double share) {
    if (steps.empty()) {
        return 0.0;
    }
    std::sort(steps.begin(), steps.end());
    return steps[static_cast<std::size_t>(
        std::lround(share * static_cast<double>(steps.size() - 1)))];
}

FrameSeamSteps measureFrameSeam(const proto::BundleView& bundle, const proto::Vec3d& light,
                                double band) {
    const renderer::BundleScene scenes(bundle, "");
    renderer::VirtualLight virtualLight;
    virtualLight.position = {light.x, light.y, light.z};
    const renderer::RenderScene scene = scenes.scene(virtualLight, scenes.bundleViewer());
    const renderer::ProjectorPixels pixels(scene.mesh, scene.projector);
    const renderer::ProjectorFrame frame = renderer::renderProjectorFrame(scene, pixels);
    const auto nearSeam = [band](double u) { return u < band || u > 1 - band; };
    FrameSeamSteps steps;
    const int w = pixels.width(), h = pixels.height();
    for (int y = 0; y < h; ++y) {
        std::optional<renderer::ProjectorPixel> left = pixels.trace(0, y);
        for (int x = 0; x + 1 < w; ++x) {
            std::optional<renderer::ProjectorPixel> right = pixels.trace(x + 1, y);
            if (left && right && nearSeam(left->point.uv.x) && nearSeam(right->point.uv.x)) {
                const float* a =
                    &frame.targetRadiance.values[(static_cast<std::size_t>(y) * w + x) * 3];
                double d2 = 0;
                for (int c = 0; c < 3; ++c) {
                    const double d = static_cast<double>(a[c + 3]) - static_cast<double>(a[c]);
                    d2 += d * d;
                }
                const bool crosses = std::fabs(left->point.uv.x - right->point.uv.x) > 0.5;
                (crosses ? steps.seam : steps.interior).push_back(std::sqrt(d2));
            }
            left = std::move(right);
        }
    }
    return steps;
}

}  // namespace vpe::testing
