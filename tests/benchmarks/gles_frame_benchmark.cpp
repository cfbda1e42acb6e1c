// SPDX-License-Identifier: MIT
// GlesFrameRenderer at 1920 × 1080, M = 10, RGB, two regions blended by a live weight preset,
// headless (llvmpipe here): ms/frame and fps with low-rank (compressed, rank 12: 24 B/texel per
// region) and full-precision (17 RGBA16F layers: 136 B/texel per region) textures, and in the
// same run a pass-through shader that samples exactly the same texture layers (GL_LINEAR,
// every layer of both regions and the weights, once per pixel, full screen) and does nothing
// else: the bandwidth floor. Frames of the renderer (render + present, i.e. glFinish; no
// readback) and of the floor alternate; medians of the timed frames after warm-up, the ratio
// the median of each pair's ratio. Besides wall time, the process's CPU time (llvmpipe's
// threads included), which hardly depends on the load other programs put on the machine. Then
// the visibility and shading passes timed apart (FramePassTimes: the GPU finishes after each),
// by a renderer that draws the visibility pass every frame: the frames above draw it once.
// The scene: a 1.3 m × 0.72 m plane (64 × 64 quads, 8192 triangles) 1.5 m in front of a
// 1920 × 1080 projector (f = 2000 px), ~90% of the pixels.
//   vpe_gles_frame_benchmark [--texture 1024] [--frames 10] [--warmup 2] [--shaders DIR]
// --shaders writes the generated shading shaders to DIR/{low_rank,full}.frag (for reading and
// for counting operations, docs/pi-headroom.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <GLES3/gl31.h>
#include <time.h>
#include <unistd.h>

#include "vpe/renderer/gles/gl_program.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"
#include "vpe/renderer/gles/headless_egl_platform.h"

#include "bake/bundle_writer.h"
#include "benchmark_bundle.h"

namespace {

namespace gles = vpe::renderer::gles;
using Clock = std::chrono::steady_clock;

constexpr int kWidth = 1920, kHeight = 1080;

vpe::bake::BundleContents contents(int size, bool lowRank) {
    vpe::bake::BundleContents c;
    c.mesh = vpe::benchmarks::planeMesh(64, 1.3f, 0.72f, -1.0f);
    c.projector = vpe::benchmarks::benchmarkProjector();
    c.settings.viewerPosition = {0.0f, 0.2f, -1.5f};
    c.settings.peakIrradiance = 2.0f;
    c.model.harmonics = 10;
    c.model.lambda = 3.14;
    c.textureWidth = c.textureHeight = size;
    const auto values = static_cast<std::size_t>(c.model.coefficientsPerTexel());
    const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
    constexpr int kRank = 12;
    for (int region = 0; region < 2; ++region) {
        vpe::bake::BundleRegion entry;
        entry.name = region == 0 ? "clay" : "glaze";
        vpe::bake::CoefficientMapData& map = entry.coefficients;
        if (lowRank) {
            map.encoding = vpe::proto::CoefficientEncoding::kLowRank;
            map.rank = kRank;
            map.mean.resize(values);
            for (std::size_t i = 0; i < values; ++i) {
                map.mean[i] = i < 3 ? 0.4f : 0.05f / static_cast<float>(i / 3);
            }
            map.basis.resize(kRank * values);
            for (std::size_t i = 0; i < map.basis.size(); ++i) {
                map.basis[i] = 0.02f * std::sin(0.1f * static_cast<float>(i + 7 * region));
            }
            map.weights.resize(texels * kRank);
            for (std::size_t i = 0; i < map.weights.size(); ++i) {
                map.weights[i] =
                    static_cast<float>((i * 2654435761u + region) % 1000) / 500.0f - 1.0f;
            }
        } else {
            map.encoding = vpe::proto::CoefficientEncoding::kFull;
            map.coefficients.resize(texels * values);
            for (std::size_t t = 0; t < texels; ++t) {
                for (std::size_t i = 0; i < values; ++i) {
                    const float wobble =
                        static_cast<float>(((t + 31 * i) * 2654435761u + region) % 1000) / 1e4f;
                    map.coefficients[t * values + i] =
                        (i < 3 ? 0.4f : 0.05f / static_cast<float>(i / 3)) + wobble;
                }
            }
        }
        c.regions.push_back(std::move(entry));
    }
    c.presets.push_back(vpe::benchmarks::stripesPreset(size));
    return c;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Wall time, and CPU time of the whole process: llvmpipe's rasterizer threads included, so the
// CPU time hardly depends on what else the machine runs.
struct FrameTime {
    double wallMs = 0;
    double cpuMs = 0;
};

double processCpuMs() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

template <typename Frame>
FrameTime timeFrame(Frame&& frame) {
    const auto start = Clock::now();
    const double cpuStart = processCpuMs();
    frame();
    return {std::chrono::duration<double, std::milli>(Clock::now() - start).count(),
            processCpuMs() - cpuStart};
}

// The bandwidth floor: the bundle's texture layers, uploaded as the renderer uploads them,
// each sampled once per pixel by a full-screen triangle.
class PassThrough {
public:
    explicit PassThrough(const vpe::proto::BundleView& bundle) {
        const auto& presets = bundle.presets();
        const vpe::proto::WeightPresetView& preset = presets.front();
        const int w = bundle.textureWidth(), h = bundle.textureHeight();
        if (preset.encoding == vpe::proto::AlphaEncoding::kUnorm8) {
            weights_ = gles::makeArrayTexture(GL_R8, w, h, preset.layers, GL_RED, GL_UNSIGNED_BYTE,
                                              preset.unorm8.data());
        } else {
            weights_ = gles::makeArrayTexture(GL_R16F, w, h, preset.layers, GL_RED, GL_HALF_FLOAT,
                                              preset.halves.data());
        }
        std::string fragment =
            "#version 310 es\nprecision highp float;\nprecision highp sampler2DArray;\n"
            "uniform sampler2DArray weights;\nuniform vec2 size;\nout vec4 colour;\n";
        std::string body =
            "void main() {\n  vec2 uv = gl_FragCoord.xy / size;\n  vec4 sum = vec4(0.0);\n";
        for (int l = 0; l < preset.layers; ++l) {
            body += "  sum.x += texture(weights, vec3(uv, " + std::to_string(l) + ".0)).x;\n";
        }
        for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
            const vpe::proto::HalfLayers& layers = bundle.regions()[r].coefficients.layers;
            regions_.push_back(gles::makeArrayTexture(GL_RGBA16F, layers.width, layers.height,
                                                      layers.layers, GL_RGBA, GL_HALF_FLOAT,
                                                      layers.halves.data()));
            layers_ += layers.layers;
            fragment += "uniform sampler2DArray region" + std::to_string(r) + ";\n";
            for (int l = 0; l < layers.layers; ++l) {
                body += "  sum += texture(region" + std::to_string(r) + ", vec3(uv, " +
                        std::to_string(l) + ".0));\n";
            }
        }
        fragment += body + "  colour = vec4(sum.xyz * 0.01, 1.0);\n}\n";
        const std::string vertex =
            "#version 310 es\nvoid main() {\n"
            "  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);\n"
            "  gl_Position = vec4(p, 0.0, 1.0);\n}\n";
        program_ = gles::GlObject::program(gles::linkProgram(
            "pass_through", gles::compileShader(GL_VERTEX_SHADER, "pass.vert", vertex),
            gles::compileShader(GL_FRAGMENT_SHADER, "pass.frag", fragment)));
        vertexArray_ = gles::GlObject::vertexArray();
    }
    int layers() const { return layers_; }
    void render(gles::RenderTarget& target) {
        glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
        glViewport(0, 0, target.width(), target.height());
        glUseProgram(program_.get());
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D_ARRAY, weights_.get());
        glUniform1i(glGetUniformLocation(program_.get(), "weights"), 0);
        for (std::size_t r = 0; r < regions_.size(); ++r) {
            glActiveTexture(GL_TEXTURE1 + static_cast<GLenum>(r));
            glBindTexture(GL_TEXTURE_2D_ARRAY, regions_[r].get());
            glUniform1i(
                glGetUniformLocation(program_.get(), ("region" + std::to_string(r)).c_str()),
                1 + static_cast<GLint>(r));
        }
        glUniform2f(glGetUniformLocation(program_.get(), "size"),
                    static_cast<float>(target.width()), static_cast<float>(target.height()));
        glBindVertexArray(vertexArray_.get());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        target.present();
        gles::checkGlError("pass-through frame");
    }

private:
    gles::GlObject weights_, program_, vertexArray_;
    std::vector<gles::GlObject> regions_;
    int layers_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
    int textureSize = 1024, frames = 10, warmup = 2;
    std::string shaderFolder;
    for (int i = 1; i + 1 < argc; i += 2) {
        const int value = std::atoi(argv[i + 1]);
        if (std::strcmp(argv[i], "--shaders") == 0) {
            shaderFolder = argv[i + 1];
        } else if (std::strcmp(argv[i], "--texture") == 0) {
            textureSize = value;
        } else if (std::strcmp(argv[i], "--frames") == 0) {
            frames = value;
        } else if (std::strcmp(argv[i], "--warmup") == 0) {
            warmup = value;
        }
    }
    const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                         ("vpe-gles-benchmark-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    int status = 0;
    try {
        std::unique_ptr<gles::GraphicsPlatform> platform = gles::createHeadlessEglPlatform();
        std::printf(
            "%s\n%dx%d, M = 10, RGB, 2 regions + live weights (8-bit preset), %d² textures, "
            "median of %d frames after %d warm-up (render + glFinish)\n",
            platform->description().c_str(), kWidth, kHeight, textureSize, frames, warmup);
        std::printf("%-12s %8s %8s %7s %9s %6s %8s %9s %6s %11s %8s\n", "", "", "frame", "",
                    "floor", "", "CPU", "CPU", "CPU", "visibility", "shading");
        std::printf("%-12s %8s %8s %7s %9s %6s %8s %9s %6s %11s %8s\n", "textures", "B/texel", "ms",
                    "fps", "ms", "ratio", "ms", "floor ms", "ratio", "pass ms", "pass ms");
        for (const bool lowRank : {true, false}) {
            const std::filesystem::path path = folder / (lowRank ? "low_rank.vpeb" : "full.vpeb");
            vpe::bake::writeBundle(path, contents(textureSize, lowRank));
            const vpe::proto::BundleFile bundle =
                vpe::proto::BundleFile::open(path, {.verifyChecksum = false});
            if (!shaderFolder.empty()) {
                std::ofstream(std::filesystem::path(shaderFolder) /
                              (lowRank ? "low_rank.frag" : "full.frag"))
                    << gles::shadingShaderSource(bundle.view());
            }
            std::unique_ptr<gles::RenderTarget> target =
                platform->createRenderTarget(kWidth, kHeight);
            int bytesPerTexel = bundle->presets().front().bytesPerTexel();
            for (const auto& region : bundle->regions()) {
                bytesPerTexel += region.coefficients.bytesPerTexel();
            }
            // Frames of the renderer and of the floor alternate, so that both see the same load
            // on a shared machine; the ratios are medians of each pair's ratio.
            std::vector<double> frameMs, frameCpuMs, floorMs, floorCpuMs, ratio, cpuRatio;
            std::vector<double> visibilityMs, shadingMs;
            {
                gles::GlesFrameRenderer renderer(bundle.view());
                PassThrough floor(bundle.view());
                gles::FrameInputs inputs;
                inputs.viewerPosition = bundle->settings().viewerPosition;
                const auto renderFrame = [&](int i) {
                    const float phi = 0.3f * static_cast<float>(i);
                    inputs.lightPosition = {0.6f * std::cos(phi), 0.6f * std::sin(phi), -1.2f};
                    renderer.render(*target, inputs);
                    target->present();
                };
                for (int i = 0; i < warmup; ++i) {
                    renderFrame(i);
                    floor.render(*target);
                }
                for (int i = 0; i < frames; ++i) {
                    const FrameTime frame = timeFrame([&] { renderFrame(warmup + i); });
                    const FrameTime pass = timeFrame([&] { floor.render(*target); });
                    frameMs.push_back(frame.wallMs);
                    frameCpuMs.push_back(frame.cpuMs);
                    floorMs.push_back(pass.wallMs);
                    floorCpuMs.push_back(pass.cpuMs);
                    ratio.push_back(frame.wallMs / pass.wallMs);
                    cpuRatio.push_back(frame.cpuMs / pass.cpuMs);
                }
            }
            {
                // The passes apart, the visibility pass drawn every frame (the renderer above
                // draws it once and reuses the ids); the GPU finishes after each pass.
                gles::GlesFrameRenderer renderer(bundle.view(), {.reuseVisibility = false});
                gles::FrameInputs inputs;
                inputs.viewerPosition = bundle->settings().viewerPosition;
                for (int i = 0; i < warmup + frames; ++i) {
                    gles::FramePassTimes times;
                    renderer.render(*target, inputs, &times);
                    target->present();
                    if (i >= warmup) {
                        visibilityMs.push_back(times.visibilityMs);
                        shadingMs.push_back(times.shadingMs);
                    }
                }
            }
            const double ms = median(frameMs);
            std::printf("%-12s %8d %8.1f %7.2f %9.1f %6.2f %8.1f %9.1f %6.2f %11.1f %8.1f\n",
                        lowRank ? "low-rank 12" : "full", bytesPerTexel, ms, 1000.0 / ms,
                        median(floorMs), median(ratio), median(frameCpuMs), median(floorCpuMs),
                        median(cpuRatio), median(visibilityMs), median(shadingMs));
            std::fflush(stdout);
            std::filesystem::remove(path);
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_gles_frame_benchmark: %s\n", error.what());
        status = 1;
    }
    std::filesystem::remove_all(folder);
    return status;
}
