// SPDX-License-Identifier: MIT
// The tests' one bundle builder: payloads and a Bundle table written straight from the schema,
// laid out, checksummed and assembled as the device reads them. No offline writer, so the
// device-only build (proto, renderer and firmware tests) uses it too. The scenes — the reader
// tests' quad (tests/proto/bundle_fixture.h) and the GLES tests' vase
// (tests/renderer/gles_test_bundle.h) — say what goes in; this says how it is written.
// Header-only: the packaged example bundles' writer (cmake/VpePackaging.cmake) compiles the
// vase's sources by path, without the test tree's libraries.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/proto/bundle_contents.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/bundle_generated.h"
#include "vpe/proto/bundle_layout.h"

namespace vpe::testing {

namespace fb = proto::fb;

// One payload of a test bundle: its name (for TestBundleSpec::editPayload), element type,
// shape and bytes.
struct TestPayload {
    std::string name;
    fb::ElementType type = fb::ElementType::Float32;
    std::vector<std::uint32_t> shape;
    std::vector<std::byte> bytes;
};

template <typename T>
TestPayload testPayload(std::string name, fb::ElementType type, std::vector<std::uint32_t> shape,
                        const std::vector<T>& values) {
    TestPayload p{std::move(name), type, std::move(shape),
                  std::vector<std::byte>(values.size() * sizeof(T))};
    std::memcpy(p.bytes.data(), values.data(), p.bytes.size());
    return p;
}

// Writes the Bundle table once the payloads are placed: placed[i] is payloads[i]'s reference.
using BundleTableWriter = std::function<flatbuffers::Offset<fb::Bundle>(
    flatbuffers::FlatBufferBuilder&, const std::vector<proto::PayloadPlacement>& placed)>;

struct TestBundleSpec {
    std::vector<TestPayload> payloads;  // in file order
    BundleTableWriter bundleTable;
    // The header's minor version (0: a bundle from before Model.theta_basis).
    std::uint16_t minorVersion = proto::kBundleMinorVersion;
    // Called for each payload reference after layout, before the metadata: the bundle can be
    // told to lie (a reference misaligned, too short or out of range while the checksum still
    // matches).
    std::function<void(const std::string& payload, proto::PayloadPlacement&)> editPayload;
};

// The payloads laid out and checksummed, behind the metadata spec.bundleTable writes.
inline std::vector<std::byte> buildTestBundle(const TestBundleSpec& spec) {
    proto::BundleLayout layout;
    std::vector<std::span<const std::byte>> bytes;
    for (const TestPayload& p : spec.payloads) {
        layout.add(p.type, p.shape);
        bytes.emplace_back(p.bytes);
    }
    const std::vector<std::uint8_t> meta =
        layout.settle([&](const std::vector<proto::PayloadPlacement>& placed) {
            std::vector<proto::PayloadPlacement> edited = placed;
            if (spec.editPayload) {
                for (std::size_t i = 0; i < edited.size(); ++i) {
                    spec.editPayload(spec.payloads[i].name, edited[i]);
                }
            }
            flatbuffers::FlatBufferBuilder b;
            fb::FinishBundleBuffer(b, spec.bundleTable(b, edited));
            return std::vector<std::uint8_t>(b.GetBufferPointer(),
                                             b.GetBufferPointer() + b.GetSize());
        });
    return proto::assembleBundle(layout, meta, bytes, spec.minorVersion);
}

// A projector (or the installation's camera) as Bundle.projector and Bundle.camera hold it;
// withoutRotation leaves R out, as a malformed writer would.
inline flatbuffers::Offset<fb::Projector> projectorTable(
    flatbuffers::FlatBufferBuilder& b, const proto::ProjectorCalibration& calibration,
    bool withoutRotation = false) {
    const fb::Mat3d intrinsics(flatbuffers::make_span(calibration.intrinsics));
    const fb::Mat3d rotation(flatbuffers::make_span(calibration.rotation));
    const auto& k = calibration.distortion;
    const fb::Distortion distortion(k[0], k[1], k[2], k[3], k[4]);
    const auto& t = calibration.translation;
    const fb::Vec3d translation(t[0], t[1], t[2]);
    return fb::CreateProjector(b, calibration.width, calibration.height, &intrinsics, &distortion,
                               withoutRotation ? nullptr : &rotation, &translation);
}

// RenderSettings' response: the gamma (2.2, 2.3, 2.4) both scenes use, or, given one, a
// sampled curve per channel (R, G, B).
struct ResponseTable {
    fb::ProjectorResponse kind = fb::ProjectorResponse::GammaResponse;
    flatbuffers::Offset<void> table;
};

inline ResponseTable responseTable(flatbuffers::FlatBufferBuilder& b,
                                   const std::array<std::vector<float>, 3>* curve) {
    if (curve != nullptr) {
        return {fb::ProjectorResponse::CurveResponse,
                fb::CreateCurveResponseDirect(b, &(*curve)[0], &(*curve)[1], &(*curve)[2]).Union()};
    }
    const fb::Rgb gamma(2.2f, 2.3f, 2.4f);
    return {fb::ProjectorResponse::GammaResponse, fb::CreateGammaResponse(b, &gamma).Union()};
}

// Writes bytes to path, whole or throwing; returns path.
inline std::filesystem::path writeBytes(const std::filesystem::path& path,
                                        const std::vector<std::byte>& bytes) {
    std::ofstream stream(path, std::ios::binary | std::ios::trunc);
    stream.write(reinterpret_cast<const char*>(bytes.data()),
                 static_cast<std::streamsize>(bytes.size()));
    if (!stream) {
        throw std::runtime_error("cannot write " + path.string());
    }
    return path;
}

}  // namespace vpe::testing
