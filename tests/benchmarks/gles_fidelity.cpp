// SPDX-License-Identifier: MIT
// How far the GLES renderer's frames are from the CPU reference with full-precision
// coefficients (exact Fourier evaluation) on a bundle — the demo's, say — under the reference
// lights (two grazing, one behind): 8-bit PSNR over the object's pixels and the whole frame,
// each light at its --gain auto. Headless EGL (llvmpipe here).
//   vpe_gles_fidelity BUNDLE [--preset NAME] [--json]
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "vpe/renderer/gles/headless_egl_platform.h"

#include "support/gpu_fidelity.h"
#include "support/reference_lights.h"

int main(int argc, char** argv) {
    std::string bundlePath, preset;
    bool json = false;
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        if (argument == "--json") {
            json = true;
        } else if (argument == "--preset" && i + 1 < argc) {
            preset = argv[++i];
        } else if (bundlePath.empty() && argument.rfind("--", 0) != 0) {
            bundlePath = argument;
        } else {
            std::fprintf(stderr, "usage: vpe_gles_fidelity BUNDLE [--preset NAME] [--json]\n");
            return 2;
        }
    }
    if (bundlePath.empty()) {
        std::fprintf(stderr, "usage: vpe_gles_fidelity BUNDLE [--preset NAME] [--json]\n");
        return 2;
    }
    try {
        const vpe::proto::BundleFile bundle = vpe::proto::BundleFile::open(bundlePath);
        std::unique_ptr<vpe::renderer::gles::GraphicsPlatform> platform =
            vpe::renderer::gles::createHeadlessEglPlatform();
        const auto results = vpe::testing::measureGpuFidelity(bundle.view(), *platform, preset);
        std::printf("%s: θs basis %d functions; GPU against the CPU reference (exact)\n",
                    bundlePath.c_str(), bundle->model().thetaBasisSize());
        std::printf("%-8s %7s %9s %12s %11s %8s\n", "light", "gain", "covered", "object dB",
                    "frame dB", "largest");
        double worstObject = std::numeric_limits<double>::infinity(), worstFrame = worstObject;
        nlohmann::json lights = nlohmann::json::array();
        for (const auto& result : results) {
            std::printf("%-8s %7.3f %9zu %12.1f %11.1f %8d\n", result.light.c_str(), result.gain,
                        result.covered, result.psnrObject, result.psnrFrame, result.largest);
            worstObject = std::min(worstObject, result.psnrObject);
            worstFrame = std::min(worstFrame, result.psnrFrame);
            const auto finite = [](double value) {
                return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json("inf");
            };
            lights.push_back({{"light", result.light},
                              {"gain", result.gain},
                              {"covered_pixels", result.covered},
                              {"psnr_object", finite(result.psnrObject)},
                              {"psnr_frame", finite(result.psnrFrame)},
                              {"largest_difference", result.largest}});
        }
        std::printf("worst: %.1f dB on the object, %.1f dB over the frame\n", worstObject,
                    worstFrame);
        if (json) {
            std::printf("%s\n", nlohmann::json({{"lights", lights},
                                                {"psnr_object_worst", worstObject},
                                                {"psnr_frame_worst", worstFrame}})
                                    .dump()
                                    .c_str());
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_gles_fidelity: %s\n", error.what());
        return 2;
    }
    return 0;
}
