// SPDX-License-Identifier: MIT
// BundleScene: a device bundle made ready for the CPU reference renderer — textures decoded
// from half floats (low-rank codes expanded), one weight preset selected, the mesh's texture
// coordinates turned from the bundle's (rows from the top) to the renderer's (OBJ/GL, v up),
// calibration and settings converted. Owns what it decoded; the RenderScene it hands out
// points into it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/cpu/render_scene.h"

namespace vpe::renderer {

class BundleScene {
public:
    // `preset` names a weight preset; empty: the first. Throws std::invalid_argument naming
    // the preset when the bundle has no such one.
    BundleScene(const proto::BundleView& bundle, const std::string& preset);

    // The scene for a light and one viewer (a tracked visitor; no viewing zone); the bundle's
    // settings give everything else.
    RenderScene scene(const VirtualLight& light, const Vec3d& viewer) const;
    // The scene for a light as the device draws the bundle: for its viewer and its viewing zone
    // (format 1.6, proto/viewing_zone.h).
    RenderScene scene(const VirtualLight& light) const;
    const proto::BundleView& bundle() const { return bundle_; }
    Vec3d bundleViewer() const;
    const std::string& presetName() const { return presetName_; }

private:
    const proto::BundleView& bundle_;
    std::string presetName_;
    std::vector<Vec3f> positions_, normals_;
    std::vector<Vec2f> uvs_;
    std::vector<std::vector<float>> coefficients_;   // per region, C per texel
    std::vector<std::vector<float>> weights_;        // per region, one per texel
    std::vector<std::vector<float>> detailNormals_;  // per region, x and y per texel, or none
    ProjectorModel projector_;
    ScreenSurface surface_;
    std::shared_ptr<const MeasuredLightMaps> measuredLight_;  // format 1.4's, when it has one
    std::shared_ptr<const FloatImage> lightShare_;            // format 1.5's, when it has one
};

// Format 1.5's share map decoded to floats (the projector's size), or none.
std::shared_ptr<const FloatImage> decodeLightShare(const proto::BundleView& bundle);

// A coefficient map decoded to floats (C per texel, bundleCoefficientIndex order).
std::vector<float> decodeCoefficientMap(const proto::CoefficientMapView& map, int coefficients);
// A map's relief decoded to floats (x and y per texel), empty when it has none.
std::vector<float> decodeDetailNormals(const proto::CoefficientMapView& map);

}  // namespace vpe::renderer
