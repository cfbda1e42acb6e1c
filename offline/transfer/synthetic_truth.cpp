// SPDX-License-Identifier: MIT
// The synthetic capture's true material as a texture.
#include "vpe/transfer/synthetic_truth.h"

#include <algorithm>
#include <cmath>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/normals/detail_normals.h"
#include "vpe/proto/surface_horizon.h"
#include "vpe/synth/microfacet_brdf.h"

namespace vpe::transfer {

namespace {

// GGX needs α > 0; the synthetic materials stay far above this.
constexpr double kMinRoughness = 0.02;

image::FloatImage readTruthImage(const std::filesystem::path& path, int channels, int width,
                                 int height) {
    image::FloatImage image = image::readImage(path);
    if (image.channels < channels ||
        (width > 0 && (image.width != width || image.height != height))) {
        throw common::InputError(
            path, "expected " + std::to_string(channels) + " channels of " +
                      (width > 0 ? std::to_string(width) + " x " + std::to_string(height)
                                 : std::string("the truth's size")) +
                      ", found " + std::to_string(image.channels) + " of " +
                      std::to_string(image.width) + " x " + std::to_string(image.height));
    }
    return image;
}

}  // namespace

SyntheticTruth::SyntheticTruth(const std::filesystem::path& capture) {
    const std::filesystem::path truth = capture / "truth";
    const image::FloatImage parameters = readTruthImage(truth / "parameters.exr", 5, 0, 0);
    width_ = parameters.width;
    height_ = parameters.height;
    const image::FloatImage normals = readTruthImage(truth / "normals.exr", 3, width_, height_);
    const image::FloatImage macro = readTruthImage(truth / "macro-normals.exr", 3, width_, height_);
    // The frame the fit measures the relief in: the capture camera's right.
    const proto::Vec3d right =
        normals::imageRightDirection(capture::openCapture(capture / "train"));

    const std::size_t texels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    parameters_.assign(texels * 6, 0.0f);
    detail_.assign(texels * 2, 0.0f);
    for (std::size_t t = 0; t < texels; ++t) {
        const float* p =
            parameters.pixels.data() + t * static_cast<std::size_t>(parameters.channels);
        std::copy_n(p, 3, parameters_.begin() + static_cast<long>(6 * t));  // albedo
        parameters_[6 * t + 3] = p[3];                                      // roughness
        parameters_[6 * t + 4] = p[4];                                      // F0
        const auto vec = [t](const image::FloatImage& image) {
            const float* v = image.pixels.data() + t * static_cast<std::size_t>(image.channels);
            return proto::Vec3d{v[0], v[1], v[2]};
        };
        const proto::Vec3d n = vec(normals), m = vec(macro);
        if (proto::dot(n, n) > 0.25 && proto::dot(m, m) > 0.25) {  // the object is there
            const proto::Vec3d d =
                normals::detailNormalOf(proto::normalized(n), proto::normalized(m), right);
            detail_[2 * t] = static_cast<float>(d.x);
            detail_[2 * t + 1] = static_cast<float>(d.y);
        }
    }
    parameterTextures_.harmonics = 0;
    parameterTextures_.width = width_;
    parameterTextures_.height = height_;
    parameterTextures_.regions = {{parameters_, {}, {}}};
    reliefTextures_ = parameterTextures_;
    reliefTextures_.regions = {{parameters_, {}, detail_}};
}

std::array<double, 3> SyntheticTruth::radiance(const renderer::SurfacePoint& point,
                                               const renderer::VirtualLight& light,
                                               const renderer::Vec3d& viewer) const {
    return radianceParts(point, light, viewer, false);
}

std::array<double, 3> SyntheticTruth::viewDependentRadiance(const renderer::SurfacePoint& point,
                                                            const renderer::VirtualLight& light,
                                                            const renderer::Vec3d& viewer) const {
    return radianceParts(point, light, viewer, true);
}

std::array<double, 3> SyntheticTruth::radianceParts(const renderer::SurfacePoint& point,
                                                    const renderer::VirtualLight& light,
                                                    const renderer::Vec3d& viewer,
                                                    bool viewDependentOnly) const {
    const auto unit = [](const proto::Vec3d& from, const proto::Vec3d& to) {
        const proto::Vec3d d{to.x - from.x, to.y - from.y, to.z - from.z};
        return proto::normalized(d);
    };
    const proto::Vec3d l = unit(point.position, light.position), v = unit(point.position, viewer);
    const proto::Vec3d n = renderer::shadingNormal(reliefTextures_, point);
    const double horizon =
        proto::horizonFactor(proto::dot(n, l), proto::dot(point.geometricNormal, l),
                             proto::dot(n, v), proto::dot(point.geometricNormal, v));
    if (horizon == 0) {
        return {0, 0, 0};
    }
    double values[6];
    renderer::sampleMaterial(parameterTextures_, point.uv, values);
    synth::MicrofacetMaterial material;
    material.albedo = {values[0], values[1], values[2]};
    material.roughness = std::max(values[3], kMinRoughness);
    material.f0 = values[4];
    proto::Vec3d f = synth::microfacetRadiance(material, n, l, v);
    if (viewDependentOnly) {
        // (ρ + π f_spec)·max(n·l, 0) less the Lambert part ρ·max(n·l, 0).
        const double lambert = std::max(proto::dot(n, l), 0.0);
        f = {f.x - material.albedo.x * lambert, f.y - material.albedo.y * lambert,
             f.z - material.albedo.z * lambert};
    }
    const std::array<double, 3> irradiance = light.irradianceAt(point.position);
    return {irradiance[0] * horizon * f.x, irradiance[1] * horizon * f.y,
            irradiance[2] * horizon * f.z};
}

}  // namespace vpe::transfer
