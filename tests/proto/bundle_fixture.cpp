// SPDX-License-Identifier: MIT
// The reader tests' quad, through the tests' one bundle builder (tests/support/test_bundle.h).
#include "bundle_fixture.h"

#include <cstdlib>
#include <stdexcept>

namespace vpe::proto::testing {

namespace {

using vpe::testing::testPayload;
using vpe::testing::TestPayload;

TestPayload halfLayers(std::string name, std::uint32_t layers, std::uint32_t width,
                       std::uint32_t height) {
    std::vector<std::uint16_t> halves(std::size_t{layers} * width * height * 4);
    for (std::size_t i = 0; i < halves.size(); ++i) {
        halves[i] = halfPattern(i);
    }
    return testPayload(std::move(name), fb::ElementType::Float16, {layers, height, width, 4},
                       halves);
}

flatbuffers::Offset<fb::Bundle> bundleTable(flatbuffers::FlatBufferBuilder& b,
                                            const RawBundleSpec& spec,
                                            const std::vector<PayloadRecord>& payloads,
                                            int coefficients) {
    const auto reference = [&](const PayloadRecord& p) { return payloadReference(b, p); };
    const auto mesh = fb::CreateMesh(b, reference(payloads[0]), reference(payloads[1]),
                                     reference(payloads[2]), reference(payloads[3]));
    const auto projector =
        vpe::testing::projectorTable(b, {.width = 1920,
                                         .height = 1080,
                                         .intrinsics = {1400, 0, 960, 0, 1400, 540, 0, 0, 1},
                                         .distortion = {0.1, -0.05, 0.001, 0.002, 0.01},
                                         .rotation = {0, 0, 1, 0, 1, 0, -1, 0, 0},  // 90° about y
                                         .translation = {0.1, -0.2, 1.5}});
    const vpe::testing::ResponseTable response =
        vpe::testing::responseTable(b, spec.curveResponse ? &spec.curve : nullptr);
    const fb::Vec3f viewer(0.0f, 0.3f, 2.0f);
    const fb::Rgb albedo(0.85f, 0.8f, 0.75f);
    const fb::Rgb ambient(0.01f, 0.02f, 0.03f);
    const auto settings = fb::CreateRenderSettings(b, &viewer, &albedo, &ambient, response.kind,
                                                   response.table, 3.5f, 0.8f);
    const auto model =
        fb::CreateModelDirect(b, static_cast<std::uint16_t>(spec.harmonics), 3.14,
                              spec.layout.c_str(), spec.thetaBasis ? &*spec.thetaBasis : nullptr);

    const auto full = [&](const PayloadRecord& p, flatbuffers::Offset<fb::Payload> detail = {}) {
        const auto layers = fb::CreateFullCoefficients(b, reference(p)).Union();
        return fb::CreateCoefficientMap(b, fb::CoefficientEncoding::FullCoefficients, layers,
                                        detail);
    };
    const auto c = static_cast<std::size_t>(coefficients);
    std::vector<float> mean(c), basis(2 * c);
    for (std::size_t i = 0; i < mean.size(); ++i) {
        mean[i] = 0.01f * static_cast<float>(i);
    }
    for (std::size_t i = 0; i < basis.size(); ++i) {
        basis[i] = -0.5f + 0.001f * static_cast<float>(i);
    }
    const auto lowRank = fb::CreateCoefficientMap(
        b, fb::CoefficientEncoding::LowRankCoefficients,
        fb::CreateLowRankCoefficientsDirect(b, 2, &mean, &basis, reference(payloads[5])).Union());
    std::vector<flatbuffers::Offset<fb::Region>> regions{
        fb::CreateRegionDirect(
            b, "base",
            full(payloads[4],
                 spec.detailNormals ? reference(payloads[9]) : flatbuffers::Offset<fb::Payload>())),
        fb::CreateRegionDirect(b, "glaze", lowRank)};
    const auto composed = full(payloads[6]);
    std::vector<flatbuffers::Offset<fb::WeightPreset>> presets{
        fb::CreateWeightPresetDirect(b, "even", reference(payloads[7])),
        fb::CreateWeightPresetDirect(b, "glazed", reference(payloads[8]))};
    const auto textures =
        fb::CreateTexturesDirect(b, spec.textureWidth, spec.textureHeight, &regions, composed,
                                 &presets, spec.wrapU.value_or(false));
    flatbuffers::Offset<fb::Projector> camera;
    if (spec.camera) {
        camera = vpe::testing::projectorTable(b, *spec.camera, spec.cameraWithoutRotation);
    }
    return fb::CreateBundle(b, mesh, projector, settings, model, textures, camera);
}

}  // namespace

float positionValue(std::size_t i) {
    return 0.125f * static_cast<float>(i) - 0.5f;
}

std::uint16_t halfPattern(std::size_t i) {
    return static_cast<std::uint16_t>(0x3000 + (i * 37) % 0x0c00);
}

std::vector<std::byte> buildRawBundle(const RawBundleSpec& spec) {
    const int coefficients = 3 * (2 * spec.harmonics + 2);
    const std::uint32_t w = spec.textureWidth;
    const std::uint32_t h = spec.textureHeight;
    std::vector<float> positions(12), normals(12, 0.0f), uvs(8);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        positions[i] = positionValue(i);
    }
    for (std::size_t v = 0; v < 4; ++v) {
        normals[3 * v + 2] = 1.0f;
        uvs[2 * v] = static_cast<float>(v % 2);
        uvs[2 * v + 1] = static_cast<float>(v / 2);
    }
    std::vector<std::uint32_t> indices{0, 1, 2, 2, 1, 3};
    if (spec.triangleIndexOverride != UINT32_MAX) {
        indices[0] = spec.triangleIndexOverride;
    }
    std::vector<std::uint8_t> even(std::size_t{2} * w * h, 128);
    for (std::size_t t = 0; t < std::size_t{w} * h; ++t) {
        even[t] = 127;
    }
    std::vector<std::uint16_t> glazed(std::size_t{2} * w * h, 0x3c00);  // 1.0
    for (std::size_t t = 0; t < std::size_t{w} * h; ++t) {
        glazed[t] = 0;
    }

    std::vector<TestPayload> payloads;
    payloads.push_back(testPayload("positions", fb::ElementType::Float32, {4, 3}, positions));
    payloads.push_back(testPayload("normals", fb::ElementType::Float32, {4, 3}, normals));
    payloads.push_back(testPayload("uvs", fb::ElementType::Float32, {4, 2}, uvs));
    payloads.push_back(testPayload("indices", fb::ElementType::UInt32, {2, 3}, indices));
    const auto layers = static_cast<std::uint32_t>((coefficients + 3) / 4);
    payloads.push_back(halfLayers("region 0", layers, w, h));
    payloads.push_back(halfLayers("region 1", 1, w, h));
    payloads.push_back(halfLayers("composed", layers, w, h));
    payloads.push_back(testPayload("preset 0", fb::ElementType::UInt8, {2, h, w}, even));
    payloads.push_back(testPayload("preset 1", fb::ElementType::Float16, {2, h, w}, glazed));
    if (spec.detailNormals) {
        std::vector<std::uint16_t> detail(std::size_t{2} * w * h);
        for (std::size_t i = 0; i < detail.size(); ++i) {
            detail[i] = halfPattern(i);  // 0.125 … 0.5: inside the unit disc
        }
        payloads.push_back(
            testPayload("region 0 detail", fb::ElementType::Float16, {h, w, 2}, detail));
    }
    return vpe::testing::buildTestBundle(
        {.payloads = std::move(payloads),
         .bundleTable =
             [&](flatbuffers::FlatBufferBuilder& b, const std::vector<PayloadRecord>& placed) {
                 return bundleTable(b, spec, placed, coefficients);
             },
         .minorVersion = spec.minorVersion,
         .editPayload = spec.editPayload});
}

void resealChecksum(std::vector<std::byte>& bytes) {
    sealBundleChecksum(bytes);
}

ScratchFolder::ScratchFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "vpe-bundle-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
        throw std::runtime_error("cannot create a scratch folder");
    }
    path_ = pattern;
}

ScratchFolder::~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

}  // namespace vpe::proto::testing
