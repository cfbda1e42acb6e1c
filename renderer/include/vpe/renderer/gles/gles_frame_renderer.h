// SPDX-License-Identifier: MIT
// GlesFrameRenderer: the projector frame of renderer/README.md on OpenGL ES 3.1, equal to the
// CPU reference (renderProjectorFrame) to within the θs basis the bundle carries.
//
// A frame does only what the light changes. Once per bundle and projector (at construction):
//   - the geometry buffer (GeometryBuffer): every projector pixel's exact ray traced on the
//     CPU by the reference's own code — position, normals, uv, the projector's 1/S;
//   - the θs material (ThetaTextures): the regions' coefficients projected onto the bundle's θs
//     basis in texture space, and the table of the basis functions;
//   - the material pass (MaterialPass): per projector pixel, the material at its uv — the
//     preset's regions blended, scaled by the viewer's horizon — packed as half floats.
// Per frame, one full-screen pass: fetch the pixel's geometry and material, look h_j(θs) up in
// the table, f = kd·max(cos θd, 0) + Σ_j u_j·h_j, the light's horizon and falloff, the
// compensation, the response. Changing the preset runs the material pass once and cross-fades
// between the old and the new material over options.presetFadeSeconds. With liveWeights, the
// regions' materials are kept apart in projector space and a preset change blends them there.
// A bundle's relief (detail normal maps) is folded into the geometry buffer's shading normal
// by the relief pass, for the selected preset, at load and at each preset change: frames pay
// nothing for it. A cross-fade fades the material; the relief switches to the new preset's at
// its start. Live weights blend the regions' materials, composed on the selected preset's relief.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/gles/frame_variant.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

// The renderer's internals (renderer/gles/, not installed).
class GeometryBuffer;
class ThetaTextures;
class MaterialPass;
class ReliefPass;
class ShadingGeometryPass;
class WeightPass;
class TileCover;
struct ShaderLayout;

struct GlesRendererOptions {
    // Largest texture side accepted, on top of GL_MAX_TEXTURE_SIZE (the Pi 4/5 guarantee).
    int maxTextureSize = 4096;
    // Keep every region's material in projector space and blend them by the preset's weights
    // there when the weights change (the weight maps stay live), instead of sampling the
    // regions' maps again: a change costs a pass of reads and writes, a frame the same as
    // without. Costs one coded material per region in memory.
    bool liveWeights = false;
    // A preset change cross-fades over this long (0: at once).
    double presetFadeSeconds = 0.5;
    // Samples of the θs table (docs/pi-headroom.md: chosen by the measured loss).
    int thetaTableSamples = 1024;
    // CPU threads tracing the geometry at load; 0: all cores.
    int threads = 0;
    // The viewer the view-dependent terms are rendered for; default the bundle's.
    std::optional<std::array<float, 3>> viewer;
};

// What changes from frame to frame.
struct FrameInputs {
    std::array<float, 3> lightPosition{0, 0, 1};  // object frame, metres
    std::array<float, 3> lightIntensity{1, 1, 1};
    bool inverseSquare = false;
    float referenceDistance = 1.0f;
    float gain = 1.0f;  // > 0; the bundle's settings hold a default
    // The frame's time (seconds, any monotonic origin): drives preset cross-fades.
    double timeSeconds = 0;
};

// Wall time of the frame's pass when asked for (render() then waits for the GPU: for
// profiling only, it serializes the pipeline).
struct FramePassTimes {
    double shadingMs = 0;
};

// What the construction cost (startup).
struct LoadTimes {
    double geometryMs = 0;  // tracing and uploading the geometry buffer
    double materialMs = 0;  // projecting, uploading the θs maps, first material pass
    double shadersMs = 0;   // compiling and linking
};

class GlesFrameRenderer {
public:
    // Uploads the bundle (a GL ES 3.1 context must be current and stay current for the
    // renderer's life; the bundle must outlive the constructor only). Throws GraphicsError
    // naming the problem (textures larger than the limits, a shader that does not compile) and
    // std::invalid_argument for a bundle it cannot render (regions without presets).
    GlesFrameRenderer(const proto::BundleView& bundle, const GlesRendererOptions& options = {});
    ~GlesFrameRenderer();
    GlesFrameRenderer(const GlesFrameRenderer&) = delete;
    GlesFrameRenderer& operator=(const GlesFrameRenderer&) = delete;

    // Selects a weight preset by name (empty: the first). After the first frame the change
    // cross-fades (fade false: at once). Throws std::invalid_argument naming the preset and
    // the ones the bundle has.
    void selectPreset(const std::string& name, bool fade = true);
    const std::string& presetName() const { return presetName_; }
    // A cross-fade is under way: the next frame differs from the last even if the light did not
    // move.
    bool animating() const { return fading_; }

    int width() const { return width_; }
    int height() const { return height_; }
    const LoadTimes& loadTimes() const { return loadTimes_; }
    // K, the θs functions each pixel evaluates (2M + 1 when the bundle carries no basis).
    int basisSize() const;

    // Renders one frame into the target (its size must be the projector's).
    void render(RenderTarget& target, const FrameInputs& inputs,
                FramePassTimes* passTimes = nullptr);

    // The frame shader of a variant as compiled (for reading and counting its operations).
    std::string frameShader(FrameVariant variant, bool inverseSquare = false) const;
    // With live weights, what a change of weights costs a pixel: the blend pass's first draw
    // (the kd codes and up to three layers of codes; for K = 4 all of it), for counting.
    std::string blendShader() const;
    // The texture-fetch floor of the next frame: a shader reading exactly the textures the
    // frame reads per pixel and doing nothing else (passThroughShaderSource), drawn into the
    // target. For benchmarks.
    void renderPassThrough(RenderTarget& target);
    // Projector pixels that see the object.
    std::size_t coveredPixels() const;
    // The variant the next frame draws.
    FrameVariant nextVariant() const;

private:
    struct FrameProgram;
    void buildFramePrograms();
    std::unique_ptr<FrameProgram> linkFrameProgram(FrameVariant variant, bool inverseSquare,
                                                   std::string source, const std::string& name);
    void bindFrameTextures();
    // Clears the target to black and readies `frame` to draw the covered tiles.
    void beginTiles(RenderTarget& target, const FrameProgram& frame);
    // The program of a variant (all linked at load).
    FrameProgram& program(FrameVariant variant, bool inverseSquare);
    std::size_t presetIndex(const std::string& name) const;
    // With a relief: folds the selected preset's into geometry1 (and, with live weights,
    // recomposes the regions' materials, whose viewer horizon follows the shading normal).
    void foldRelief();
    // The layout the frame's shaders are generated for: the textures' and the measured light.
    ShaderLayout frameLayout() const;

    std::string bundleName_;
    proto::RenderSettings settings_;
    int width_ = 0, height_ = 0;
    std::array<float, 3> viewer_{};
    std::vector<std::array<float, 3>> zone_;  // the bundle's viewing zone, unless a viewer is given
    GlesRendererOptions options_;
    std::unique_ptr<GeometryBuffer> geometry_;
    std::unique_ptr<ThetaTextures> textures_;
    std::unique_ptr<MaterialPass> materialPass_;
    std::unique_ptr<ReliefPass> reliefPass_;  // only for a bundle with a relief
    std::unique_ptr<ShadingGeometryPass> shadingPass_;
    std::unique_ptr<WeightPass> weightPass_;  // live weights with presets only
    std::vector<std::string> presetNames_;
    std::string presetName_;
    std::size_t preset_ = 0;
    // The coded materials and the measured light's textures (GL objects: gles_frame_renderer.cpp).
    struct Textures;
    std::unique_ptr<Textures> gpu_;
    int shown_ = 0;  // which of gpu_'s composed materials is the current preset's
    bool fading_ = false;
    bool renderedOnce_ = false;
    std::optional<double> fadeStart_;
    std::vector<std::unique_ptr<FrameProgram>> programs_;  // per variant and falloff, as needed
    std::vector<std::unique_ptr<FrameProgram>> passThroughPrograms_;  // built when first asked
    std::unique_ptr<TileCover> tiles_;
    std::array<float, 9> mixingInverse_{};  // the measured light's X⁻¹, column-major (mat3)
    bool measuredLight_ = false;
    LoadTimes loadTimes_;
};

}  // namespace vpe::renderer::gles
