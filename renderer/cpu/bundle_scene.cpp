// SPDX-License-Identifier: MIT
#include "vpe/renderer/cpu/bundle_scene.h"

#include <algorithm>
#include <stdexcept>

#include "vpe/proto/half_float.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/response_function.h"

namespace vpe::renderer {

std::vector<float> decodeCoefficientMap(const proto::CoefficientMapView& map, int coefficients) {
    const proto::HalfLayers& layers = map.layers;
    const std::size_t texels =
        static_cast<std::size_t>(layers.width) * static_cast<std::size_t>(layers.height);
    const std::size_t c = static_cast<std::size_t>(coefficients);
    // Value i of texel t lives in layer i / 4, component i % 4.
    const auto half = [&](std::size_t t, std::size_t i) {
        return proto::halfToFloat(layers.halves[((i / 4) * texels + t) * 4 + i % 4]);
    };
    std::vector<float> out(texels * c);
    if (map.encoding == proto::CoefficientEncoding::kFull) {
        for (std::size_t t = 0; t < texels; ++t) {
            for (std::size_t i = 0; i < c; ++i) {
                out[t * c + i] = half(t, i);
            }
        }
        return out;
    }
    const std::size_t rank = static_cast<std::size_t>(map.rank);
    std::vector<float> weights(rank);
    for (std::size_t t = 0; t < texels; ++t) {
        for (std::size_t r = 0; r < rank; ++r) {
            weights[r] = half(t, r);
        }
        for (std::size_t i = 0; i < c; ++i) {
            float value = map.mean[i];
            for (std::size_t r = 0; r < rank; ++r) {
                value += weights[r] * map.basis[r * c + i];
            }
            out[t * c + i] = value;
        }
    }
    return out;
}

std::vector<float> decodeDetailNormals(const proto::CoefficientMapView& map) {
    std::vector<float> out(map.detailNormals.size());
    std::transform(map.detailNormals.begin(), map.detailNormals.end(), out.begin(),
                   proto::halfToFloat);
    return out;
}

BundleScene::BundleScene(const proto::BundleView& bundle, const std::string& preset)
    : bundle_(bundle) {
    const proto::MeshView& mesh = bundle.mesh();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        positions_.push_back(
            {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
        normals_.push_back({mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]});
        uvs_.push_back({mesh.uvs[2 * v], 1.0f - mesh.uvs[2 * v + 1]});  // rows from the top → v up
    }
    const proto::WeightPresetView* chosen = nullptr;
    for (const proto::WeightPresetView& candidate : bundle.presets()) {
        if (preset.empty() || candidate.name == preset) {
            chosen = &candidate;
            break;
        }
    }
    if (chosen == nullptr) {
        std::string names;
        for (const proto::WeightPresetView& candidate : bundle.presets()) {
            names += (names.empty() ? "" : ", ") + std::string(candidate.name);
        }
        throw std::invalid_argument(bundle.name() + ": no weight preset '" + preset +
                                    "' (it has: " + names + ")");
    }
    presetName_ = std::string(chosen->name);
    const int c = bundle.model().coefficientsPerTexel();
    const std::size_t texels = static_cast<std::size_t>(bundle.textureWidth()) *
                               static_cast<std::size_t>(bundle.textureHeight());
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        coefficients_.push_back(decodeCoefficientMap(bundle.regions()[r].coefficients, c));
        detailNormals_.push_back(decodeDetailNormals(bundle.regions()[r].coefficients));
        std::vector<float> alpha(texels);
        for (std::size_t t = 0; t < texels; ++t) {
            alpha[t] = chosen->encoding == proto::AlphaEncoding::kUnorm8
                           ? static_cast<float>(chosen->unorm8[r * texels + t]) / 255.0f
                           : proto::halfToFloat(chosen->halves[r * texels + t]);
        }
        weights_.push_back(std::move(alpha));
    }

    projector_.camera = proto::cameraOf(bundle.projector());
    const proto::RenderSettings& settings = bundle.settings();
    projector_.response = proto::responseFunctionOf(settings.response);
    projector_.peakIrradiance = static_cast<double>(settings.peakIrradiance);
    for (std::size_t ch = 0; ch < 3; ++ch) {
        surface_.albedo[ch] = static_cast<double>(settings.screenAlbedo[ch]);
        surface_.ambientIrradiance[ch] = static_cast<double>(settings.ambientIrradiance[ch]);
    }
    if (const auto& measured = bundle.radiometry()) {
        auto maps = std::make_shared<MeasuredLightMaps>();
        maps->width = static_cast<int>(bundle.projector().width);
        maps->height = static_cast<int>(bundle.projector().height);
        const std::size_t pixels = static_cast<std::size_t>(maps->width) * maps->height;
        maps->irradiance.resize(3 * pixels);
        maps->floor.resize(3 * pixels);
        for (std::size_t p = 0; p < pixels; ++p) {
            for (std::size_t k = 0; k < 3; ++k) {
                maps->irradiance[3 * p + k] = proto::halfToFloat(measured->irradiance[4 * p + k]);
                maps->floor[3 * p + k] = proto::halfToFloat(measured->floor[4 * p + k]);
            }
        }
        maps->mixingInverse = inverse3x3(measured->mixing);
        maps->inverseResponse = proto::InverseResponseTable(projector_.response);
        measuredLight_ = std::move(maps);
    }
    lightShare_ = decodeLightShare(bundle);
}

std::shared_ptr<const FloatImage> decodeLightShare(const proto::BundleView& bundle) {
    const std::optional<proto::BlendView>& blend = bundle.blend();
    if (!blend) {
        return nullptr;
    }
    auto share = std::make_shared<FloatImage>(static_cast<int>(bundle.projector().width),
                                              static_cast<int>(bundle.projector().height));
    std::transform(blend->share.begin(), blend->share.end(), share->values.begin(),
                   proto::halfToFloat);
    return share;
}

Vec3d BundleScene::bundleViewer() const {
    const auto& v = bundle_.settings().viewerPosition;
    return {static_cast<double>(v[0]), static_cast<double>(v[1]), static_cast<double>(v[2])};
}

RenderScene BundleScene::scene(const VirtualLight& light) const {
    RenderScene drawn = scene(light, bundleViewer());
    drawn.viewingZone = bundle_.settings().viewingZone;
    return drawn;
}

RenderScene BundleScene::scene(const VirtualLight& light, const Vec3d& viewer) const {
    RenderScene scene;
    scene.mesh.positions = positions_;
    scene.mesh.normals = normals_;
    scene.mesh.uvs = uvs_;
    scene.mesh.indices = bundle_.mesh().indices;
    scene.projector = projector_;
    scene.surface = surface_;
    scene.material.harmonics = bundle_.model().harmonics;
    scene.material.width = bundle_.textureWidth();
    scene.material.height = bundle_.textureHeight();
    scene.material.wrapU = bundle_.textureWrapsU();
    for (std::size_t r = 0; r < coefficients_.size(); ++r) {
        scene.material.regions.push_back({coefficients_[r], weights_[r], detailNormals_[r]});
    }
    scene.light = light;
    scene.viewer = viewer;
    scene.measuredLight = measuredLight_;
    scene.lightShare = lightShare_;
    return scene;
}

}  // namespace vpe::renderer
