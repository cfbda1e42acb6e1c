// SPDX-License-Identifier: MIT
// The reader tests' small bundle — a quad, M = 1 — written by the tests' one bundle builder
// (tests/support/test_bundle.h; no offline writer in the device build). Unlike the writer, the
// builder can be told to lie: every payload reference passes through a hook before it goes into
// the metadata, so a test can make one misaligned, too short or out of range while the checksum
// still matches.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/bundle_contents.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/bundle_generated.h"
#include "vpe/proto/bundle_layout.h"

#include "../support/test_bundle.h"

namespace vpe::proto::testing {

// A payload's reference as the metadata will hold it (offset, size, type, shape).
using PayloadRecord = PayloadPlacement;

// Defaults describe a valid bundle: 4 vertices and 2 triangles; M = 1 (C = 12); textures
// 4 x 2 with region 0 'base' full, region 1 'glaze' low-rank (rank 2), a full composed map and
// presets 'even' (8-bit) and 'glazed' (half floats); a gamma response; no θs basis.
struct RawBundleSpec {
    std::uint32_t textureWidth = 4;
    std::uint32_t textureHeight = 2;
    int harmonics = 1;
    std::string layout = "fourier_brdf:k_major_rgb";
    // The header's minor version (0: a bundle from before Model.theta_basis).
    std::uint16_t minorVersion = kBundleMinorVersion;
    // Model.theta_basis as written; nullopt leaves the field out, as 1.0 writers did.
    std::optional<std::vector<float>> thetaBasis;
    // Textures.wrap_u as written; nullopt leaves the field out, as 1.0 and 1.1 writers did.
    std::optional<bool> wrapU;
    bool curveResponse = false;
    std::array<std::vector<float>, 3> curve{
        {{0.0f, 0.25f, 1.0f}, {0.0f, 0.5f, 1.0f}, {0.0f, 0.75f, 1.0f}}};
    std::uint32_t triangleIndexOverride = UINT32_MAX;  // written as index 0 when set
    // Region 0 carries a relief ("region 0 detail", Float16 [h, w, 2], format 1.2); without,
    // the field stays absent, as 1.0 and 1.1 writers left it.
    bool detailNormals = false;
    // Bundle.camera as written (format 1.3); nullopt leaves the field out, as 1.0–1.2 writers
    // did. cameraWithoutRotation writes the table with its rotation left out.
    std::optional<ProjectorCalibration> camera;
    bool cameraWithoutRotation = false;
    // Called for each payload — "positions", "normals", "uvs", "indices", "region 0",
    // "region 1", "composed", "preset 0", "preset 1", "region 0 detail" — after layout, before
    // the metadata.
    std::function<void(const std::string& payload, PayloadRecord&)> editPayload;
};

// The payload values the builder writes, for round-trip checks.
float positionValue(std::size_t i);
std::uint16_t halfPattern(std::size_t i);

std::vector<std::byte> buildRawBundle(const RawBundleSpec& spec = {});

// Recomputes the header's checksum after a test changed bytes behind it.
void resealChecksum(std::vector<std::byte>& bytes);

// A fresh folder, removed with everything in it on destruction.
class ScratchFolder {
public:
    ScratchFolder();
    ~ScratchFolder();
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

using vpe::testing::writeBytes;

}  // namespace vpe::proto::testing
