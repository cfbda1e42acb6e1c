// SPDX-License-Identifier: MIT
// vpe bake: the screen texture (one composed map, or the quilted region maps with named
// weight-map presets the device can switch live), the screen object's mesh, the projector's
// calibration and response, the installation's camera, and the viewer, combined into one device
// bundle.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/bake/projector_blend.h"
#include "vpe/bake/scan_placement.h"
#include "vpe/proto/bundle_contents.h"
#include "vpe/proto/pinhole_camera.h"

namespace vpe::bake {

struct PresetSpec {
    std::string name;
    std::string weights;  // a vpe compose --weights spec, one entry per region
};

struct BakeOptions {
    // The texture: a model file, or a vpe quilt folder with at least one preset.
    std::filesystem::path texture;
    std::filesystem::path quilt;
    std::vector<PresetSpec> presets;
    // The screen object: an OBJ/PLY file, or empty for the built-in vase.
    std::filesystem::path mesh;
    double meshMetresPerUnit = 1.0;
    // A scan folder (vpe scan's --out): the projector and camera from its calibration, the mesh
    // placed in it by registration (scan_placement.h), or the scan's own surface without a mesh.
    std::filesystem::path scan;
    registration::RegistrationOptions registration;
    // The projector: a calibration file, or empty for the demo projector at `demoDistance`.
    std::filesystem::path projector;
    std::optional<int> projectorWidth, projectorHeight;
    std::optional<double> projectorMetresPerUnit;
    double demoDistance = 0.6;
    // The installation's camera, object frame → camera (format 1.3's Bundle.camera: the
    // device's lamp tracker maps image positions to light directions with it). Unset: the
    // `projector` file's cam_K, cam_kc, cam_width, cam_height when it has them, at the
    // origin (a procam file's object frame is its camera's); else none.
    std::optional<proto::PinholeCamera> camera;
    std::string response = "2.2";  // gamma, r,g,b gammas, or a CSV curve
    // The light measured on site (vpe radiometry's --out): the bundle carries its maps
    // (format 1.4) and its response replaces `response`, albedo and ambient.
    std::filesystem::path radiometry;
    proto::RenderSettings settings;
    // Carry the textures' relief (detail normal maps) into the bundle when they have one.
    bool relief = true;
    bool lowRank = true;
    int rank = 12;
    // The θs basis the device renders in (proto/MODEL.md, "Rendering in a θs basis"): K
    // functions fitted to the textures as they will be rendered (vpe bake --theta-basis);
    // 0 stores none, and the device renders the 2M + 1 harmonics exactly. Unset: 4, or as many
    // as M has independent θs functions when that is fewer.
    std::optional<int> thetaBasis;
    unsigned threads = 1;
};

struct BakeReport {
    int textureWidth = 0, textureHeight = 0, harmonics = 0, regions = 0;
    std::size_t vertices = 0, triangles = 0;
    // The textures tile in u, so the bundle's sampling wraps; and whether the mesh's u wraps
    // (when it does and the textures do not, u = 0 | 1 is a visible seam).
    bool wrapU = false;
    bool meshWrapsU = false;
    int bytesPerTexel = 0;  // per region, as stored (coefficients)
    bool relief = false;    // the bundle carries detail normal maps (4 bytes a texel more)
    // Low-rank codes: share of the coefficient variance kept, and the RMS coefficient error,
    // worst over the regions.
    double explainedVariance = 1.0;
    double coefficientRms = 0.0;
    // The θs basis: K functions (0: none), and the share of the textures' θs second moment
    // (∫₀^π g², every texel and channel) they keep.
    int thetaBasis = 0;
    double thetaEnergyKept = 1.0;
    // The bundle carries the installation's camera (at this resolution).
    bool camera = false;
    int cameraWidth = 0, cameraHeight = 0;
    // With measured light: the projector pixels the mesh covers, and how many of them were
    // completed from their neighbours (the camera did not see them).
    std::size_t radiometryCovered = 0, radiometryCompleted = 0;
    // With a scan: where the object stands in the camera's frame, and how it was found.
    std::optional<ScanPlacement> placement;
    std::uint64_t bytes = 0;
    std::uint32_t checksum = 0;
};

// Reads, checks, encodes and writes atomically. Throws InputError naming the input at fault.
BakeReport bakeScene(const BakeOptions& options, const std::filesystem::path& out);

// One projector of a show of several on one object: its calibration file or its scan (every
// scan made with the same camera: the first one's registration places the object for all,
// which keeps them in one frame even where a registration alone cannot tell — a surface of
// revolution's turn), its measured light (optional), and the bundle to write.
struct ShowProjector {
    std::filesystem::path calibration, scan, radiometry;
    std::filesystem::path out;
};

struct ShowReport {
    std::vector<BakeReport> bundles;  // one per projector, in order
    ProjectorBlend blend;             // the shares the bundles carry, and the surface's reach
};

// Several projectors on one object (bundle format 1.5): the textures encoded once, the
// projectors placed, their shares of the light computed from the geometry (blendProjectors),
// and one bundle written per projector with its share. `options`' projector, scan and
// radiometry are ignored (each ShowProjector brings its own). Throws InputError naming the
// input at fault.
ShowReport bakeShow(const BakeOptions& options, const std::vector<ShowProjector>& projectors,
                    const BlendOptions& blend);

}  // namespace vpe::bake
