// SPDX-License-Identifier: MIT
// GlesFrameRenderer: the projector frame of renderer/README.md on OpenGL ES 3.1 — the same
// conventions and math as the CPU reference (renderProjectorFrame), from a device bundle's
// mesh and textures uploaded as they are stored.
//
// Two passes. (1) Visibility, drawn once (it depends on the mesh and the projector only) and
// reused: every triangle is rasterized as a conservative cover of its distorted image (its
// box, or its triangle with each edge pushed out by the edge's bend, grown by a margin), and
// each fragment intersects the EXACT ray of its projector pixel — the pixel centre undistorted
// on the CPU with undistortNormalized, kept in an RG32F map — with the triangle
// (Möller–Trumbore, the CPU ray caster's rule); misses are discarded and the ray depth is the
// fragment depth, so the id buffer (R32UI) holds the nearest hit of the same ray the CPU casts:
// coverage and silhouettes match the reference pixel for pixel despite lens distortion, with
// no intermediate image to resample. (2) Shading, every frame, one full-screen triangle: per
// pixel the hit's barycentrics, the two-sided normal, the uv, the Fourier BRDF's basis values
// (fourier_brdf_glsl.h), each region's BRDF from its coefficients (bilinear, GL_LINEAR, clamp
// to edge; low-rank codes evaluated in the low-rank space) weighted by the preset, the light,
// and the projector compensation; the drive levels go to the target as RGBA8. The shading
// shader is generated per bundle (shadingShaderSource) as straight-line code.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/gles/gl_program.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

struct GlesRendererOptions {
    // Largest texture side accepted, on top of GL_MAX_TEXTURE_SIZE (the Pi 4/5 guarantee).
    int maxTextureSize = 4096;
    // The visibility pass depends on the mesh and the projector only, fixed for the renderer's
    // life: it is drawn on the first frame (and when the target's orientation changes) and its
    // ids reused. false draws it every frame (to profile it, or to test that reuse changes
    // nothing).
    bool reuseVisibility = true;
};

// What changes from frame to frame.
struct FrameInputs {
    std::array<float, 3> lightPosition{0, 0, 1};  // object frame, metres
    std::array<float, 3> lightIntensity{1, 1, 1};
    bool inverseSquare = false;
    float referenceDistance = 1.0f;
    std::array<float, 3> viewerPosition{0, 0, 1};
    float gain = 1.0f;  // > 0; the bundle's settings hold a default
};

// Wall time of each pass when asked for (render() then waits for the GPU after each: for
// profiling only, it serializes the pipeline).
struct FramePassTimes {
    bool visibilityDrawn = false;  // false: the ids were reused (visibilityMs 0)
    double visibilityMs = 0;
    double shadingMs = 0;
};

// The shading pass's fragment shader for a bundle, as GlesFrameRenderer compiles it: generated
// per bundle, M, the regions' encodings and the low-rank means and bases baked in as constants
// (for inspection, and for counting its operations: docs/pi-headroom.md).
std::string shadingShaderSource(const proto::BundleView& bundle);

class GlesFrameRenderer {
public:
    // Uploads the bundle (a GL ES 3.1 context must be current and stay current for the
    // renderer's life; the bundle must outlive the constructor only). Throws GraphicsError
    // naming the problem: textures larger than the limits, too many regions for the texture
    // units, a response curve with too many samples, a shader that does not compile.
    GlesFrameRenderer(const proto::BundleView& bundle, const GlesRendererOptions& options = {});
    ~GlesFrameRenderer();
    GlesFrameRenderer(const GlesFrameRenderer&) = delete;
    GlesFrameRenderer& operator=(const GlesFrameRenderer&) = delete;

    // Selects a weight preset by name (empty: the first). Throws std::invalid_argument naming
    // the preset and the ones the bundle has.
    void selectPreset(const std::string& name);
    const std::string& presetName() const { return presetName_; }

    // The projector's size: the target must have it.
    int width() const { return width_; }
    int height() const { return height_; }

    // Renders one frame into the target (its size must be the projector's). With `passTimes`,
    // finishes the GPU's work before, between and after the passes and times each.
    void render(RenderTarget& target, const FrameInputs& inputs,
                FramePassTimes* passTimes = nullptr);

private:
    void uploadMesh(const proto::BundleView& bundle);
    void uploadTextures(const proto::BundleView& bundle, int maxSize);
    void buildPrograms(const proto::BundleView& bundle);
    void ensureVisibilityBuffer();

    int width_ = 0, height_ = 0;
    int harmonics_ = 0;
    std::size_t triangles_ = 0;
    std::string bundleName_;
    std::string presetName_;
    std::vector<std::string> presetNames_;
    std::vector<GlObject> presetTextures_;
    std::size_t preset_ = 0;
    std::vector<GlObject> regionTextures_;
    GlObject curveTexture_;
    GlObject triangleTable_, rays_;
    GlObject visibilityProgram_, shadingProgram_;
    GlObject vertexArray_;
    GlObject idTexture_, depthBuffer_, idFramebuffer_;
    bool reuseVisibility_ = true;
    int visibilityOrientation_ = -1;  // the ids' topRowAtGlOrigin (0, 1), −1 none yet
    // Settings and calibration as uniforms.
    std::array<float, 9> rotation_{};
    std::array<float, 3> translation_{}, center_{};
    std::array<float, 4> intrinsics_{};  // fx, fy, cx, cy
    float skew_ = 0;
    std::array<float, 5> distortion_{};
    float depthScale_ = 1;
    std::array<float, 3> albedo_{}, ambient_{};
    float peakIrradiance_ = 1;
    bool curveResponse_ = false;
    std::array<std::vector<float>, 3> curve_;  // normalized, r(1) = 1
};

}  // namespace vpe::renderer::gles
