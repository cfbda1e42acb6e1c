// SPDX-License-Identifier: MIT
// How long the CPU reference takes for a full projector frame: 1920 × 1080, a 25.6k-triangle
// vase filling most of the frame, M = 10, two regions. Run by hand; prints seconds.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"

#include "test_scenes.h"

using namespace vpe::renderer;

namespace {

// Wall-clock seconds; `cpu` gets the process's CPU seconds (all threads), which stay
// meaningful when other work shares the machine.
template <typename Work>
double seconds(Work&& work, double& cpu) {
    const std::clock_t cpuStart = std::clock();
    const auto start = std::chrono::steady_clock::now();
    work();
    cpu = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main() {
    const testing::OwnedMesh mesh = testing::makeVaseMesh(128, 100);
    testing::OwnedMaterial material =
        testing::makeMaterial(10, 256, 256, [](int x, int y, int k, int c) {
            return k == 0 ? 0.4 + 0.1 * c : 0.05 / (1 + k) * std::cos(0.1 * (x + y));
        });
    testing::addRegion(
        material, [](int, int, int k, int) { return k == 0 ? 0.3 : 0.02; },
        [](int x, int) { return 0.5 + 0.5 * std::sin(0.05 * x); });
    for (std::size_t i = 0; i < material.weights[0].size(); ++i) {
        material.weights[0][i] = 1.0f - material.weights[1][i];
    }
    RenderScene scene;
    scene.mesh = mesh.view();
    scene.material = material.view();
    scene.projector.camera =
        vpe::proto::cameraLookingAt(1920, 1080, 16.0, {0.25, 0.12, 0.55}, {0, 0.075, 0});
    scene.projector.camera.distortion = {-0.08, 0.03, 0.001, -0.0005, 0.0};
    scene.projector.response = vpe::proto::ResponseFunction::gamma(2.2);
    scene.projector.peakIrradiance = 3.0;
    scene.light.position = {0.4, 0.5, 0.6};
    const vpe::proto::PinholeCamera viewer =
        vpe::proto::cameraLookingAt(1920, 1080, 18.0, {-0.2, 0.09, 0.6}, {0, 0.075, 0});
    scene.viewer = viewer.center();

    std::printf("mesh: %zu triangles; projector 1920x1080\n", mesh.indices.size() / 3);
    for (const int threads : {1, 2}) {
        ProjectorFrame frame;
        double cpu = 0;
        const double t =
            seconds([&] { frame = renderProjectorFrame(scene, {.threads = threads}); }, cpu);
        std::printf(
            "renderProjectorFrame, %d thread(s): %.2f s wall, %.2f s CPU (%zu pixels on "
            "the vase, %.2f%% clipped)\n",
            threads, t, cpu, frame.stats.coveredPixels, 100 * frame.stats.clippedFraction);
        if (threads == 2) {
            double simulateCpu = 0, directCpu = 0;
            const double s =
                seconds([&] { simulateVisitorView(scene, frame.level, viewer, {.threads = 2}); },
                        simulateCpu);
            const double d =
                seconds([&] { renderDirectView(scene, viewer, {.threads = 2}); }, directCpu);
            std::printf(
                "1920x1080 views, 2 threads: simulateVisitorView %.2f s wall, %.2f s CPU; "
                "renderDirectView %.2f s wall, %.2f s CPU\n",
                s, simulateCpu, d, directCpu);
        }
    }
    return 0;
}
