// SPDX-License-Identifier: MIT
// GlesFrameRenderer: the load-time passes and the frame (see the header).
#include "vpe/renderer/gles/gles_frame_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>
#include <stdexcept>
#include <utility>

#include <GLES3/gl31.h>

#include "vpe/proto/half_float.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/measured_light.h"
#include "vpe/renderer/cpu/projector_pixels.h"

#include "geometry_buffer.h"
#include "material_pass.h"
#include "relief_pass.h"
#include "shading_geometry_pass.h"
#include "shading_glsl.h"
#include "texture_formats.h"
#include "theta_textures.h"
#include "tile_cover.h"
#include "weight_pass.h"

namespace vpe::renderer::gles {

namespace {

// Texture units of the frame: the position 0, the shading geometry 1, the θs table 2, the
// measured light 3–4, the response inverse 5 (measured, or the level table), the material's codes
// and kd codes 6–7, fading the old material's 8–9.
constexpr int kUnitPosition = 0, kUnitShading = 1, kUnitTable = 2, kUnitMeasuredIrradiance = 3,
              kUnitMeasuredFloor = 4, kUnitResponse = 5, kUnitMaterial = 6, kUnitMaterialFrom = 8;

// The frame looks the level table up at r·(N − 1)/N + ½/N: the factor is folded into the
// radiance scale and the ambient (vpeProjectorLevelTable).
constexpr double kLevelCoordinateScale =
    static_cast<double>(kProjectorLevelSamples - 1) / kProjectorLevelSamples;

// A projector-sized RGBA16F texture from a bundle's half floats (4 a pixel, rows from the top:
// the frame fetches it at the pixel it shades, as the geometry buffer).
GlObject halfTexture(int width, int height, std::span<const std::uint16_t> halves) {
    GlObject texture = GlObject::texture();
    glBindTexture(GL_TEXTURE_2D, texture.get());
    glTexStorage2D(GL_TEXTURE_2D, 1, kMeasuredFormat, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_HALF_FLOAT, halves.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return texture;
}
constexpr double kPi = 3.14159265358979323846;

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void bind(int unit, GLenum kind, unsigned texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
    glBindTexture(kind, texture);
}

// The bundle's mesh as the CPU renderer takes it (uv with v up), owning its arrays.
struct OwnedRenderMesh {
    std::vector<Vec3f> positions, normals;
    std::vector<Vec2f> uvs;
    RenderMesh view;

    explicit OwnedRenderMesh(const proto::MeshView& mesh) {
        for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
            positions.push_back(
                {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
            normals.push_back(
                {mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]});
            uvs.push_back({mesh.uvs[2 * v], 1.0f - mesh.uvs[2 * v + 1]});  // rows from the top
        }
        view = {positions, normals, uvs, mesh.indices};
    }
};

ProjectorModel projectorOf(const proto::BundleView& bundle) {
    ProjectorModel projector;
    projector.camera = proto::cameraOf(bundle.projector());
    projector.peakIrradiance = static_cast<double>(bundle.settings().peakIrradiance);
    return projector;
}

proto::ThetaBasis thetaBasisOf(const proto::BundleView& bundle) {
    const proto::BundleModel& model = bundle.model();
    if (model.thetaBasis.empty()) {
        return proto::ThetaBasis::full(model.harmonics);
    }
    return proto::ThetaBasis::orthonormal(model.harmonics, model.thetaBasis);
}

}  // namespace

// A frame program and its uniforms, looked up once when linked.
struct GlesFrameRenderer::FrameProgram {
    FrameVariant variant = FrameVariant::kStatic;
    bool inverseSquare = false;
    std::string source;
    GlObject program;
    GLint topRow = -1, row = -1, size = -1, light = -1, radianceScale = -1, ambient = -1, fade = -1;
};

// The GL textures the renderer owns beside its passes' (out of the public header, which names
// no GL type).
struct GlesFrameRenderer::Textures {
    // Composed materials: [shown_] the current preset's, the other the previous one's while
    // fading. With live weights also one per region, which a preset change blends.
    std::array<CodedMaterial, 2> composed;
    std::vector<CodedMaterial> regionMaterials;
    // Format 1.4's measured light: F and D as RGBA16F projector-sized textures, and the
    // response's inverse table. Empty without one.
    GlObject measuredIrradiance, measuredFloor, inverseResponse;
    GlObject levelTable;  // without measured light: the response inverse (projectorLevelTable)
};

GlesFrameRenderer::GlesFrameRenderer(const proto::BundleView& bundle,
                                     const GlesRendererOptions& options)
    : bundleName_(bundle.name()),
      settings_(bundle.settings()),
      options_(options),
      gpu_(std::make_unique<Textures>()) {
    const proto::ProjectorCalibration& calibration = bundle.projector();
    width_ = static_cast<int>(calibration.width);
    height_ = static_cast<int>(calibration.height);
    viewer_ = options.viewer.value_or(settings_.viewerPosition);
    if (!options.viewer) {  // one given viewer (a tracked visitor) replaces the zone
        zone_ = settings_.viewingZone;
    }
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    const int maxSize = std::min(maxTexture, options.maxTextureSize);
    if (width_ > maxSize || height_ > maxSize) {
        throw GraphicsError(bundleName_ + ": projector " + std::to_string(width_) + "x" +
                            std::to_string(height_) + " is larger than the texture limit " +
                            std::to_string(maxSize));
    }
    if (options.thetaTableSamples < 2 || options.thetaTableSamples > maxTexture) {
        throw std::invalid_argument(bundleName_ + ": a θs table of " +
                                    std::to_string(options.thetaTableSamples) + " samples (2 … " +
                                    std::to_string(maxTexture) + ")");
    }

    auto start = Clock::now();
    {
        const OwnedRenderMesh mesh(bundle.mesh());
        const ProjectorPixels pixels(mesh.view, projectorOf(bundle), decodeLightShare(bundle));
        geometry_ =
            std::make_unique<GeometryBuffer>(pixels, options.threads, ReliefPass::needed(bundle));
    }
    loadTimes_.geometryMs = msSince(start);

    start = Clock::now();
    textures_ = std::make_unique<ThetaTextures>(bundle, thetaBasisOf(bundle),
                                                options.thetaTableSamples, maxSize);
    for (const proto::WeightPresetView& preset : bundle.presets()) {
        presetNames_.emplace_back(preset.name);
    }
    loadTimes_.materialMs = msSince(start);

    if (const auto& measured = bundle.radiometry()) {
        if (const auto& blend = bundle.blend()) {
            // The share divides F once here (sharedIrradiance, as the CPU reference): the
            // frame aims for s · (L − D) at no cost per frame.
            std::vector<std::uint16_t> shared(measured->irradiance.begin(),
                                              measured->irradiance.end());
            for (std::size_t p = 0; p < blend->share.size(); ++p) {
                const float share = proto::halfToFloat(blend->share[p]);
                for (std::size_t k = 0; k < 3; ++k) {
                    shared[4 * p + k] = proto::floatToHalf(
                        sharedIrradiance(proto::halfToFloat(shared[4 * p + k]), share));
                }
            }
            gpu_->measuredIrradiance = halfTexture(width_, height_, shared);
        } else {
            gpu_->measuredIrradiance = halfTexture(width_, height_, measured->irradiance);
        }
        gpu_->measuredFloor = halfTexture(width_, height_, measured->floor);
        const std::array<double, 9> inverse = inverse3x3(measured->mixing);
        for (std::size_t row = 0; row < 3; ++row) {
            for (std::size_t column = 0; column < 3; ++column) {
                mixingInverse_[3 * column + row] = static_cast<float>(inverse[3 * row + column]);
            }
        }
        // The response above black, inverted once into the table the frame looks up.
        const proto::InverseResponseTable table(proto::responseFunctionOf(settings_.response),
                                                kInverseResponseSamples);
        std::vector<std::uint16_t> texels(4 * static_cast<std::size_t>(table.samples()), 0);
        for (int i = 0; i < table.samples(); ++i) {
            for (int c = 0; c < 3; ++c) {
                texels[4 * static_cast<std::size_t>(i) + static_cast<std::size_t>(c)] =
                    proto::floatToHalf(table.levels(c)[static_cast<std::size_t>(i)]);
            }
        }
        gpu_->inverseResponse = makeTexture2D(kMeasuredFormat, table.samples(), 1, GL_RGBA,
                                              GL_HALF_FLOAT, texels.data(), TextureFilter::kLinear);
        measuredLight_ = true;
    } else {
        // The response inverse as a table (projectorLevelTable): three filtered fetches, no pow.
        if (maxTexture < kProjectorLevelSamples) {  // (the GPU's: V3D's is 4096)
            throw GraphicsError(
                bundleName_ + ": the response table's " + std::to_string(kProjectorLevelSamples) +
                " samples exceed the GPU's largest texture (" + std::to_string(maxTexture) + ")");
        }
        const std::vector<float> table =
            projectorLevelTable(settings_.response, kProjectorLevelSamples);
        std::vector<std::uint16_t> texels(4 * static_cast<std::size_t>(kProjectorLevelSamples), 0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(kProjectorLevelSamples); ++i) {
            for (std::size_t c = 0; c < 3; ++c) {
                texels[4 * i + c] = proto::floatToHalf(table[3 * i + c]);
            }
        }
        gpu_->levelTable = makeTexture2D(kLevelTableFormat, kProjectorLevelSamples, 1, GL_RGBA,
                                         GL_HALF_FLOAT, texels.data(), TextureFilter::kLinear);
    }

    start = Clock::now();
    tiles_ = std::make_unique<TileCover>(width_, height_, geometry_->coveredTiles());
    const ViewerEyes eyes{viewer_, zone_};
    materialPass_ = std::make_unique<MaterialPass>(*textures_, *geometry_, *tiles_, eyes);
    shadingPass_ = std::make_unique<ShadingGeometryPass>(*geometry_, *tiles_, eyes);
    if (geometry_->relief()) {
        reliefPass_ = std::make_unique<ReliefPass>(bundle, *geometry_, *textures_, *tiles_);
    }
    buildFramePrograms();
    loadTimes_.shadersMs = msSince(start);

    start = Clock::now();
    gpu_->composed[0] = materialPass_->makeTarget();
    gpu_->composed[1] = materialPass_->makeTarget();
    if (options.liveWeights) {
        if (textures_->presetCount() > 0) {
            weightPass_ = std::make_unique<WeightPass>(*textures_, *geometry_, *tiles_);
        }
        for (int r = 0; r < textures_->layout().regions; ++r) {
            gpu_->regionMaterials.push_back(materialPass_->makeTarget());
            if (!reliefPass_) {  // with a relief, selectPreset composes them on its normals
                materialPass_->composeRegion(gpu_->regionMaterials.back(), r);
            }
        }
    }
    selectPreset("", false);
    glFinish();
    loadTimes_.materialMs += msSince(start);
    checkGlError(bundleName_ + ": uploading the bundle");
}

GlesFrameRenderer::~GlesFrameRenderer() = default;

int GlesFrameRenderer::basisSize() const {
    return textures_->layout().basisSize;
}

std::unique_ptr<GlesFrameRenderer::FrameProgram> GlesFrameRenderer::linkFrameProgram(
    FrameVariant variant, bool inverseSquare, std::string source, const std::string& name) {
    auto frame = std::make_unique<FrameProgram>();
    frame->variant = variant;
    frame->inverseSquare = inverseSquare;
    frame->source = std::move(source);
    const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
    unsigned fragment = 0;
    try {
        fragment = compileShader(GL_FRAGMENT_SHADER, name, frame->source);
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    frame->program = GlObject::program(linkProgram(name, vertex, fragment));
    const GLuint program = frame->program.get();
    const auto location = [program](const char* uniform) {
        return glGetUniformLocation(program, uniform);
    };
    glUseProgram(program);
    glUniform1i(location("uPosition"), kUnitPosition);
    glUniform1i(location("uShading"), kUnitShading);
    glUniform1i(location("uThetaTable"), kUnitTable);
    glUniform1i(location("uMeasuredIrradiance"), kUnitMeasuredIrradiance);
    glUniform1i(location("uMeasuredFloor"), kUnitMeasuredFloor);
    glUniform1i(location("uInverseResponse"), kUnitResponse);
    glUniform1i(location("uProjectorLevel"), kUnitResponse);
    if (measuredLight_) {
        glUniformMatrix3fv(location("uMixingInverse"), 1, GL_FALSE, mixingInverse_.data());
    }
    glUniform1i(location("uMaterial"), kUnitMaterial);
    glUniform1i(location("uMaterialDiffuse"), kUnitMaterial + 1);
    glUniform1i(location("uMaterialFrom"), kUnitMaterialFrom);
    glUniform1i(location("uMaterialFromDiffuse"), kUnitMaterialFrom + 1);
    frame->topRow = location("uTopRowAtOrigin");
    frame->row = location("uRow");
    frame->size = location("uSize");
    frame->light = location("uLightPosition");
    frame->radianceScale = location("uRadianceScale");
    frame->ambient = location("uAmbient");
    frame->fade = location("uFade");
    return frame;
}

void GlesFrameRenderer::buildFramePrograms() {
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    if (kUnitMaterialFrom + 2 > units) {
        throw GraphicsError(
            bundleName_ + ": a frame needs " + std::to_string(kUnitMaterialFrom + 2) +
            " texture units, more than the " + std::to_string(units) + " the GPU has");
    }
    // Every program at load: a first cross-fade or a falloff switched on must not wait for a
    // compile, and a shader's errors show at once.
    for (const FrameVariant variant : {FrameVariant::kStatic, FrameVariant::kFade}) {
        for (const bool inverseSquare : {false, true}) {
            program(variant, inverseSquare);
        }
    }
}

GlesFrameRenderer::FrameProgram& GlesFrameRenderer::program(FrameVariant variant,
                                                            bool inverseSquare) {
    for (const auto& frame : programs_) {
        if (frame->variant == variant && frame->inverseSquare == inverseSquare) {
            return *frame;
        }
    }
    programs_.push_back(linkFrameProgram(variant, inverseSquare,
                                         frameShader(variant, inverseSquare),
                                         std::string("frame-") + frameVariantName(variant) +
                                             (inverseSquare ? "-falloff" : "") + ".frag"));
    return *programs_.back();
}

std::string GlesFrameRenderer::frameShader(FrameVariant variant, bool inverseSquare) const {
    return frameShaderSource(frameLayout(), variant, settings_, inverseSquare);
}

std::string GlesFrameRenderer::blendShader() const {
    const ShaderLayout layout = frameLayout();
    return composePassShaderSource(layout, 0, std::min(3, layout.materialLayers()), true);
}

ShaderLayout GlesFrameRenderer::frameLayout() const {
    ShaderLayout layout = textures_->layout();
    layout.measuredLight = measuredLight_;
    return layout;
}

FrameVariant GlesFrameRenderer::nextVariant() const {
    return fading_ ? FrameVariant::kFade : FrameVariant::kStatic;
}

std::size_t GlesFrameRenderer::presetIndex(const std::string& name) const {
    for (std::size_t i = 0; i < presetNames_.size(); ++i) {
        if (name.empty() || presetNames_[i] == name) {
            return i;
        }
    }
    std::string names;
    for (const std::string& candidate : presetNames_) {
        names += (names.empty() ? "" : ", ") + candidate;
    }
    throw std::invalid_argument(bundleName_ + ": no weight preset '" + name + "' (it has: " +
                                (presetNames_.empty() ? std::string("none") : names) + ")");
}

void GlesFrameRenderer::selectPreset(const std::string& name, bool fade) {
    if (presetNames_.empty()) {
        if (!name.empty()) {
            throw std::invalid_argument(bundleName_ + ": no weight preset '" + name +
                                        "' (it has none)");
        }
        foldRelief();
        materialPass_->composeRegion(gpu_->composed[static_cast<std::size_t>(shown_)], 0);
        return;
    }
    const std::size_t next = presetIndex(name);
    const bool crossFade =
        fade && renderedOnce_ && options_.presetFadeSeconds > 0 && next != preset_;
    if (crossFade) {
        // Fading already: the new fade starts from whichever material was showing more.
        shown_ = 1 - shown_;
        fading_ = true;
        fadeStart_.reset();
    } else {
        fading_ = false;
    }
    const bool changed = next != preset_ || !renderedOnce_;
    preset_ = next;
    presetName_ = presetNames_[next];
    if (changed) {
        foldRelief();
    }
    const CodedMaterial& target = gpu_->composed[static_cast<std::size_t>(shown_)];
    if (options_.liveWeights) {
        // The regions' materials blended in projector space: a pass of reads and writes, not a
        // resampling of every region's maps.
        materialPass_->blendRegions(target, gpu_->regionMaterials, weightPass_->alpha(preset_));
    } else {
        materialPass_->composePreset(target, preset_);
    }
}

void GlesFrameRenderer::foldRelief() {
    if (!reliefPass_) {
        shadingPass_->run();  // the traced normals: the same every time, packed on the first
        return;
    }
    if (presetNames_.empty()) {
        reliefPass_->composeRegion(0);
    } else {
        reliefPass_->composePreset(preset_);
    }
    shadingPass_->run();
    if (options_.liveWeights) {
        for (std::size_t r = 0; r < gpu_->regionMaterials.size(); ++r) {
            materialPass_->composeRegion(gpu_->regionMaterials[r], static_cast<int>(r));
        }
    }
}

void GlesFrameRenderer::render(RenderTarget& target, const FrameInputs& inputs,
                               FramePassTimes* passTimes) {
    if (target.width() != width_ || target.height() != height_) {
        throw GraphicsError("render target " + std::to_string(target.width()) + "x" +
                            std::to_string(target.height()) + " is not the projector's " +
                            std::to_string(width_) + "x" + std::to_string(height_));
    }
    if (!(inputs.gain > 0)) {
        throw std::invalid_argument("gain must be positive");
    }
    float fadeProgress = 1.0f;
    if (fading_) {
        if (!fadeStart_) {
            fadeStart_ = inputs.timeSeconds;
        }
        const double progress = (inputs.timeSeconds - *fadeStart_) / options_.presetFadeSeconds;
        if (progress >= 1.0 || !std::isfinite(progress)) {
            fading_ = false;
        } else {
            fadeProgress = static_cast<float>(std::max(progress, 0.0));
        }
    }
    const FrameProgram& frame = program(nextVariant(), inputs.inverseSquare);
    if (passTimes != nullptr) {
        glFinish();
    }
    const auto start = Clock::now();

    bindFrameTextures();
    beginTiles(target, frame);
    // The light in the positions' cube (in double, then rounded), whose side is the unit.
    const GeometryBuffer::Cube& cube = geometry_->cube();
    glUniform3f(frame.light,
                static_cast<float>((static_cast<double>(inputs.lightPosition[0]) - cube.low[0]) /
                                   cube.side),
                static_cast<float>((static_cast<double>(inputs.lightPosition[1]) - cube.low[1]) /
                                   cube.side),
                static_cast<float>((static_cast<double>(inputs.lightPosition[2]) - cube.low[2]) /
                                   cube.side));
    // π/ρ·L = gain · I · (d_ref/d)² · H · f · π/ρ: the constants folded per channel, with the
    // distance in the cube's units (d = side · d_cube) and f in the coding's unit; with measured
    // light L itself (its F carries the albedo).
    std::array<float, 3> scale{}, ambient{};
    const double reference = inputs.inverseSquare
                                 ? static_cast<double>(inputs.referenceDistance) *
                                       static_cast<double>(inputs.referenceDistance) /
                                       (cube.side * cube.side)
                                 : 1.0;
    const double unit = static_cast<double>(textures_->coding().frameUnit());
    for (std::size_t c = 0; c < 3; ++c) {
        scale[c] = static_cast<float>(
            static_cast<double>(inputs.gain) * static_cast<double>(inputs.lightIntensity[c]) *
            reference * unit *
            (measuredLight_
                 ? 1.0
                 : kPi / static_cast<double>(settings_.screenAlbedo[c]) * kLevelCoordinateScale));
        ambient[c] = static_cast<float>(static_cast<double>(settings_.ambientIrradiance[c]) *
                                        kLevelCoordinateScale);
    }
    glUniform3fv(frame.radianceScale, 1, scale.data());
    glUniform3fv(frame.ambient, 1, ambient.data());
    glUniform1f(frame.fade, fadeProgress);
    tiles_->draw();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    renderedOnce_ = true;
    if (passTimes != nullptr) {
        glFinish();
        passTimes->shadingMs = msSince(start);
    }
    checkGlError(bundleName_ + ": rendering a frame");
}

void GlesFrameRenderer::beginTiles(RenderTarget& target, const FrameProgram& frame) {
    // Black everywhere, then the covered tiles shaded (the rest can only be black).
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    glViewport(0, 0, width_, height_);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glUseProgram(frame.program.get());
    glUniform1i(frame.topRow, target.topRowAtGlOrigin() ? 1 : 0);
    // The projector's row of a fragment at window y (a pixel centre: exact in float).
    if (target.topRowAtGlOrigin()) {
        glUniform2f(frame.row, 0.0f, 1.0f);
    } else {
        glUniform2f(frame.row, static_cast<float>(height_) - 0.5f, -1.0f);
    }
    glUniform2f(frame.size, static_cast<float>(width_), static_cast<float>(height_));
}

void GlesFrameRenderer::bindFrameTextures() {
    bind(kUnitPosition, GL_TEXTURE_2D, shadingPass_->position().get());
    bind(kUnitShading, GL_TEXTURE_2D, shadingPass_->shading().get());
    bind(kUnitTable, GL_TEXTURE_2D, textures_->table().get());
    if (measuredLight_) {
        bind(kUnitMeasuredIrradiance, GL_TEXTURE_2D, gpu_->measuredIrradiance.get());
        bind(kUnitMeasuredFloor, GL_TEXTURE_2D, gpu_->measuredFloor.get());
        bind(kUnitResponse, GL_TEXTURE_2D, gpu_->inverseResponse.get());
    } else {
        bind(kUnitResponse, GL_TEXTURE_2D, gpu_->levelTable.get());
    }
    const CodedMaterial& shown = gpu_->composed[static_cast<std::size_t>(shown_)];
    const CodedMaterial& previous = gpu_->composed[static_cast<std::size_t>(1 - shown_)];
    bind(kUnitMaterial, GL_TEXTURE_2D_ARRAY, shown.codes.get());
    bind(kUnitMaterial + 1, GL_TEXTURE_2D, shown.diffuse.get());
    bind(kUnitMaterialFrom, GL_TEXTURE_2D_ARRAY, previous.codes.get());
    bind(kUnitMaterialFrom + 1, GL_TEXTURE_2D, previous.diffuse.get());
}

void GlesFrameRenderer::renderPassThrough(RenderTarget& target) {
    const FrameVariant variant = nextVariant();
    FrameProgram* floor = nullptr;
    for (const auto& candidate : passThroughPrograms_) {
        floor = candidate->variant == variant ? candidate.get() : floor;
    }
    if (floor == nullptr) {
        passThroughPrograms_.push_back(
            linkFrameProgram(variant, false, passThroughShaderSource(frameLayout(), variant),
                             std::string("floor-") + frameVariantName(variant) + ".frag"));
        floor = passThroughPrograms_.back().get();
    }
    bindFrameTextures();
    beginTiles(target, *floor);
    tiles_->draw();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError(bundleName_ + ": the pass-through floor");
}

std::size_t GlesFrameRenderer::coveredPixels() const {
    return geometry_->coveredPixels();
}

}  // namespace vpe::renderer::gles
