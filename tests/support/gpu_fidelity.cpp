// SPDX-License-Identifier: MIT
// measureGpuFidelity: GPU frames against the exact CPU reference (see the header).
#include "support/gpu_fidelity.h"

#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/projector_pixels.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"

#include "support/reference_lights.h"

namespace vpe::testing {

namespace {

// vpe render --gain auto's default clipping share.
constexpr double kClippedFraction = 0.005;

}  // namespace

std::vector<GpuFidelity> measureGpuFidelity(const proto::BundleView& bundle,
                                            renderer::gles::GraphicsPlatform& platform,
                                            const std::string& preset) {
    namespace gles = renderer::gles;
    const renderer::BundleScene scene(bundle, preset);
    const renderer::RenderScene any = scene.scene({});
    const renderer::ProjectorPixels pixels(any.mesh, any.projector, any.lightShare);
    gles::GlesFrameRenderer gpu(bundle);
    gpu.selectPreset(scene.presetName(), false);
    std::unique_ptr<gles::RenderTarget> target =
        platform.createRenderTarget(gpu.width(), gpu.height());
    std::vector<GpuFidelity> results;
    for (const ReferenceLight& light : referenceLights()) {
        renderer::VirtualLight virtualLight;
        virtualLight.position = light.position;
        const renderer::RenderScene lit = scene.scene(virtualLight);  // as the device draws it
        renderer::RenderOptions options;
        renderer::ProjectorFrame reference = renderer::renderProjectorFrame(lit, pixels, options);
        options.gain = renderer::gainForClippedFraction(reference, kClippedFraction);
        if (options.gain < 1) {
            reference = renderer::renderProjectorFrame(lit, pixels, options);
        }
        gles::FrameInputs inputs;
        inputs.lightPosition = {static_cast<float>(light.position.x),
                                static_cast<float>(light.position.y),
                                static_cast<float>(light.position.z)};
        inputs.gain = static_cast<float>(options.gain);
        gpu.render(*target, inputs);
        target->present();
        const std::vector<std::uint8_t> rgba = target->readRgba8();
        const LevelError error = levelError(reference, rgba);
        GpuFidelity result;
        result.light = light.name;
        result.gain = options.gain;
        result.covered = reference.stats.coveredPixels;
        result.psnrObject = psnr(error.squared8, error.count, 255.0);
        result.psnrFrame = psnr(error.squared8Frame, error.frameCount, 255.0);
        result.largest = error.largest8;
        results.push_back(result);
    }
    return results;
}

}  // namespace vpe::testing
