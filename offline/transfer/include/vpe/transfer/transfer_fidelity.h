// SPDX-License-Identifier: MIT
// Transfer fidelity (`vpe transfer`): how much the screen object, seen by a visitor, looks like
// the captured material. The true material of a `vpe synth` capture (synthetic_truth.h) is
// rendered directly on the bundle's object, and compared with what the pipeline renders there
// from the fitted model baked into the bundle (the CPU reference's direct view) — same mesh,
// same texture layout, same camera — under lights and from views the capture never had:
// grazing, from below the capture's lowest light, around the back.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/render_scene.h"
#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::transfer {

// A visitor's position and the virtual light's, object frame, metres.
struct TransferView {
    std::string name;
    std::string description;
    renderer::Vec3d viewer;
    renderer::Vec3d light;
};

// The views, placed around an object of the given bounding box: the viewer and the light each
// 4 heights from its centre, in directions given by azimuth (0 = +z, the front; 90° = +x) and
// elevation.
std::vector<TransferView> transferViews(const renderer::Vec3d& lower, const renderer::Vec3d& upper);

struct TransferOptions {
    std::filesystem::path capture;   // what `vpe synth --out` wrote
    std::filesystem::path bundle;    // `vpe bake --texture MODEL.exr` of a fit of that capture
    std::filesystem::path out;       // per view: truth, pipeline, difference pictures; empty: none
    std::vector<std::string> views;  // names; empty: all
    int viewWidth = 480, viewHeight = 360;
    double fovDegrees = 20;
    // A diagnostic: render the pipeline with the truth's relief instead of the bundle's, to
    // separate what the relief's estimate costs from what the BRDF's does.
    bool trueRelief = false;
    int threads = 0;
};

struct ViewFidelity {
    std::string name;
    double psnr = 0;        // dB, 8-bit sRGB, over the object's pixels either picture lights
    double ssim = 0;        // mean SSIM over the same pixels
    double psnrObject = 0;  // dB, over all the object's pixels (dark ones too)
    double litShare = 0;    // of the object's pixels, lit in either picture
    double exposure = 0;    // applied to both: the truth's 99th percentile at 0.8
    std::size_t objectPixels = 0;
};

struct TransferReport {
    std::vector<ViewFidelity> views;
    double psnr = 0;       // mean over the views
    double ssim = 0;       // mean over the views
    double worstPsnr = 0;  // the lowest view
    std::string worstView;
    int textureWidth = 0, textureHeight = 0;
    bool relief = false;  // the bundle carries a relief
    // Mean angle between the bundle's relief (flat without one) and the truth's, over texels.
    double reliefErrorDegrees = 0;
    double seconds = 0;
};

class SyntheticTruth;

// The bounding box of a bundle's mesh (object frame, metres): where the checks' visitors look.
struct MeshBounds {
    renderer::Vec3d lower, upper;
    renderer::Vec3d centre() const {
        return {0.5 * (lower.x + upper.x), 0.5 * (lower.y + upper.y), 0.5 * (lower.z + upper.z)};
    }
};
MeshBounds meshBounds(const std::vector<float>& positions);

// The unit direction at an azimuth (0 = +z, the front; 90° = +x) and an elevation, degrees.
renderer::Vec3d directionAt(double azimuthDegrees, double elevationDegrees);

// The true material seen by `camera` on the scene's mesh under its light (no cast shadows):
// what both checks compare against. With `viewDependent`, also its part that depends on where
// the camera stands (SyntheticTruth::viewDependentRadiance), the camera's size.
renderer::RgbImage renderTruthView(const renderer::RenderScene& scene, const SyntheticTruth& truth,
                                   const proto::PinholeCamera& camera, int threads,
                                   renderer::RgbImage* viewDependent = nullptr);

// The exposure both pictures are shown at: the 99th percentile of the lit pixels' brightest
// channel at 0.8 (as `vpe render` previews do), taken from the truth.
double truthExposure(const renderer::RgbImage& image, const renderer::MaskImage& coverage);

// Throws InputError when an input is missing or they do not fit together (the bundle's texture
// is not the truth's size).
TransferReport measureTransferFidelity(const TransferOptions& options);

}  // namespace vpe::transfer
