// SPDX-License-Identifier: MIT
// ThetaTextures: project, reorder and upload (see the header).
#include "theta_textures.h"

#include <GLES3/gl31.h>

#include "vpe/renderer/cpu/theta_material.h"
#include "vpe/renderer/gles/graphics_platform.h"

#include "material_codes.h"
#include "texture_formats.h"

namespace vpe::renderer::gles {

ThetaTextures::ThetaTextures(const proto::BundleView& bundle, const proto::ThetaBasis& basis,
                             int tableSamples, int maxSize)
    : coding_(basis.size) {
    layout_.basisSize = basis.size;
    layout_.regions = static_cast<int>(bundle.regions().size());
    layout_.tableSamples = tableSamples;
    const int w = bundle.textureWidth(), h = bundle.textureHeight();
    if (w > maxSize || h > maxSize) {
        throw GraphicsError(bundle.name() + ": textures " + std::to_string(w) + "x" +
                            std::to_string(h) + " are larger than the limit " +
                            std::to_string(maxSize) + " (GL_MAX_TEXTURE_SIZE and 4096)");
    }
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    if (layout_.mapLayers() > maxLayers || layout_.regions > maxLayers) {
        throw GraphicsError(bundle.name() + ": " + std::to_string(layout_.mapLayers()) +
                            " material layers or " + std::to_string(layout_.regions) +
                            " regions exceed GL_MAX_ARRAY_TEXTURE_LAYERS " +
                            std::to_string(maxLayers));
    }
    // Maps that tile around the object repeat in u, as the CPU reference samples them.
    const TextureWrapS wrapS =
        bundle.textureWrapsU() ? TextureWrapS::kRepeat : TextureWrapS::kClamp;
    layout_.wrapU = bundle.textureWrapsU();
    const auto texels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    const auto values = static_cast<std::size_t>(layout_.materialValues());
    const auto layers = static_cast<std::size_t>(layout_.mapLayers());
    // One region at a time (its map, then its upload): the CPU holds one map, not all.
    std::vector<float> layered(layers * texels * 4, 0.0f);
    for (const proto::RegionView& region : bundle.regions()) {
        const std::vector<float> material = thetaMaterialMap(region.coefficients, basis);
        coding_.cover(material);
        // Texel-major values → layer-major RGBA (value i in layer i / 4, component i % 4).
        for (std::size_t t = 0; t < texels; ++t) {
            for (std::size_t i = 0; i < values; ++i) {
                layered[((i / 4) * texels + t) * 4 + i % 4] = material[t * values + i];
            }
        }
        // GL rounds the floats to half floats on upload (RGBA16F from GL_FLOAT data).
        maps_.push_back(makeArrayTexture(GL_RGBA16F, w, h, static_cast<int>(layers), GL_RGBA,
                                         GL_FLOAT, layered.data(), TextureFilter::kLinear, wrapS));
    }
    // The frame evaluates f in the coding's unit: kd's codes decode to [0, 1] by the sampler.
    layout_.diffuseOffset = coding_.diffuseLow() / coding_.frameUnit();
    for (const proto::WeightPresetView& preset : bundle.presets()) {
        if (preset.encoding == proto::AlphaEncoding::kUnorm8) {
            weights_.push_back(makeArrayTexture(GL_R8, w, h, preset.layers, GL_RED,
                                                GL_UNSIGNED_BYTE, preset.unorm8.data(),
                                                TextureFilter::kLinear, wrapS));
        } else {
            weights_.push_back(makeArrayTexture(GL_R16F, w, h, preset.layers, GL_RED, GL_HALF_FLOAT,
                                                preset.halves.data(), TextureFilter::kLinear,
                                                wrapS));
        }
    }
    if (weights_.empty() && layout_.regions > 1) {
        throw std::invalid_argument(bundle.name() + ": " + std::to_string(layout_.regions) +
                                    " regions and no weight preset to blend them");
    }
    // The table: row r holds h_j for j = 4r … 4r+3 in RGBA, sample s at texel s, each function
    // scaled by its code step over the frame's unit (material_codes.h).
    const std::vector<float> scaled =
        scaledThetaTable(proto::ThetaTable::of(basis, tableSamples).values, coding_);
    const int rows = layout_.tableRows();
    std::vector<float> table(static_cast<std::size_t>(rows * tableSamples) * 4, 0.0f);
    for (int s = 0; s < tableSamples; ++s) {
        for (int j = 0; j < basis.size; ++j) {
            table[(static_cast<std::size_t>((j / 4) * tableSamples + s)) * 4 +
                  static_cast<std::size_t>(j % 4)] =
                scaled[static_cast<std::size_t>(s * basis.size + j)];
        }
    }
    table_ = makeTexture2D(kThetaTableFormat, tableSamples, rows, GL_RGBA, GL_FLOAT, table.data(),
                           TextureFilter::kLinear);
    checkGlError(bundle.name() + ": uploading the θs material");
}

}  // namespace vpe::renderer::gles
