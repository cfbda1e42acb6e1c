// SPDX-License-Identifier: MIT
// A small but complete device bundle for the GLES renderer's tests, written by the tests' one
// bundle builder (tests/support/test_bundle.h; no offline writer: the device-only build runs
// these tests too): a vase seen by a 160 × 120 projector with lens distortion, M = 3, two
// regions ('base' full, 'glaze' low-rank), presets 'stripes' (8-bit) and 'radial' (half
// floats), a gamma or a sampled response; optionally with textures that wrap in u and the seam
// u = 0 | 1 turned to the projector, and optionally a relief on 'base', and optionally the
// installation's camera.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/proto/pinhole_camera.h"

namespace vpe::renderer::testing {

struct GlesBundleSpec {
    int projectorWidth = 160, projectorHeight = 120;
    int textureWidth = 32, textureHeight = 24;
    int harmonics = 3;
    int lowRank = 3;
    bool curveResponse = false;
    bool distortion = true;
    // k1, k2, p1, p2, k3 when `distortion`.
    std::array<double, 5> distortionCoefficients{0.09, -0.12, 0.0015, -0.001, 0.02};
    // The vase's quads around and along its axis: fewer means longer, more bent edges.
    int vaseSegments = 48, vaseRings = 24;
    // The textures tile in u (Textures.wrap_u): sampling wraps around the vase.
    bool wrapU = false;
    // The vase turned half a turn about its axis, so that u = 0 | 1 faces the projector.
    bool seamInFront = false;
    // Region 'base' carries a relief (format 1.2: a detail normal map tilting up to ~30°);
    // 'glaze' none, so presets blend a relief with a flat region.
    bool relief = false;
    // The installation's camera (format 1.3, Bundle.camera), object frame → camera; none when
    // unset.
    std::optional<proto::PinholeCamera> camera;
    // Format 1.4's measured light: irradiance and floor maps that vary across the projector
    // (a stain, a brighter corner), crosstalk, and the curve response taken as above black.
    bool measuredLight = false;
};

std::vector<std::byte> buildGlesTestBundle(const GlesBundleSpec& spec = {});

// The bundle written to a fresh temporary file and mapped; the file is removed on destruction.
class MappedTestBundle {
public:
    explicit MappedTestBundle(const GlesBundleSpec& spec = {});
    ~MappedTestBundle();
    MappedTestBundle(const MappedTestBundle&) = delete;
    MappedTestBundle& operator=(const MappedTestBundle&) = delete;
    const proto::BundleView& view() const { return file_.view(); }

private:
    static std::filesystem::path write(const GlesBundleSpec& spec);
    std::filesystem::path path_;
    proto::BundleFile file_;
};

}  // namespace vpe::renderer::testing
