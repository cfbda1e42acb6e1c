// SPDX-License-Identifier: MIT
// The raw bundle builder for the reader's tests.
#include "bundle_fixture.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/bundle_layout.h"

namespace vpe::proto::testing {

namespace {

struct PlannedPayload {
    std::string name;
    PayloadRecord record;
    std::vector<std::byte> bytes;
};

template <typename T>
std::vector<std::byte> bytesOf(const std::vector<T>& values) {
    std::vector<std::byte> bytes(values.size() * sizeof(T));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

PlannedPayload payload(std::string name, fb::ElementType type, std::vector<std::uint32_t> shape,
                       std::vector<std::byte> bytes) {
    PlannedPayload p;
    p.name = std::move(name);
    p.record.type = type;
    p.record.shape = std::move(shape);
    p.record.size = bytes.size();
    p.bytes = std::move(bytes);
    return p;
}

PlannedPayload halfLayers(std::string name, std::uint32_t layers, std::uint32_t width,
                          std::uint32_t height) {
    std::vector<std::uint16_t> halves(std::size_t{layers} * width * height * 4);
    for (std::size_t i = 0; i < halves.size(); ++i) {
        halves[i] = halfPattern(i);
    }
    return payload(std::move(name), fb::ElementType::Float16, {layers, height, width, 4},
                   bytesOf(halves));
}

flatbuffers::Offset<fb::Payload> reference(flatbuffers::FlatBufferBuilder& b,
                                           const PlannedPayload& p) {
    return fb::CreatePayloadDirect(b, p.record.offset, p.record.size, p.record.type,
                                   &p.record.shape);
}

std::vector<std::uint8_t> metadata(const RawBundleSpec& spec,
                                   const std::vector<PlannedPayload>& payloads, int coefficients) {
    flatbuffers::FlatBufferBuilder b;
    const auto mesh = fb::CreateMesh(b, reference(b, payloads[0]), reference(b, payloads[1]),
                                     reference(b, payloads[2]), reference(b, payloads[3]));
    const std::array<double, 9> k{1400, 0, 960, 0, 1400, 540, 0, 0, 1};
    const std::array<double, 9> r{0, 0, 1, 0, 1, 0, -1, 0, 0};  // 90° about y
    const fb::Mat3d intrinsics(flatbuffers::make_span(k));
    const fb::Mat3d rotation(flatbuffers::make_span(r));
    const fb::Distortion distortion(0.1, -0.05, 0.001, 0.002, 0.01);
    const fb::Vec3d translation(0.1, -0.2, 1.5);
    const auto projector =
        fb::CreateProjector(b, 1920, 1080, &intrinsics, &distortion, &rotation, &translation);
    flatbuffers::Offset<void> response;
    fb::ProjectorResponse kind = fb::ProjectorResponse::GammaResponse;
    if (spec.curveResponse) {
        kind = fb::ProjectorResponse::CurveResponse;
        response = fb::CreateCurveResponseDirect(b, &spec.curve[0], &spec.curve[1], &spec.curve[2])
                       .Union();
    } else {
        const fb::Rgb gamma(2.2f, 2.3f, 2.4f);
        response = fb::CreateGammaResponse(b, &gamma).Union();
    }
    const fb::Vec3f viewer(0.0f, 0.3f, 2.0f);
    const fb::Rgb albedo(0.85f, 0.8f, 0.75f);
    const fb::Rgb ambient(0.01f, 0.02f, 0.03f);
    const auto settings =
        fb::CreateRenderSettings(b, &viewer, &albedo, &ambient, kind, response, 3.5f, 0.8f);
    const auto model =
        fb::CreateModelDirect(b, static_cast<std::uint16_t>(spec.harmonics), 3.14,
                              spec.layout.c_str(), spec.thetaBasis ? &*spec.thetaBasis : nullptr);

    const auto full = [&](const PlannedPayload& p, flatbuffers::Offset<fb::Payload> detail = {}) {
        const auto layers = fb::CreateFullCoefficients(b, reference(b, p)).Union();
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
        fb::CreateLowRankCoefficientsDirect(b, 2, &mean, &basis, reference(b, payloads[5]))
            .Union());
    std::vector<flatbuffers::Offset<fb::Region>> regions{
        fb::CreateRegionDirect(
            b, "base",
            full(payloads[4], spec.detailNormals ? reference(b, payloads[9])
                                                 : flatbuffers::Offset<fb::Payload>())),
        fb::CreateRegionDirect(b, "glaze", lowRank)};
    const auto composed = full(payloads[6]);
    std::vector<flatbuffers::Offset<fb::WeightPreset>> presets{
        fb::CreateWeightPresetDirect(b, "even", reference(b, payloads[7])),
        fb::CreateWeightPresetDirect(b, "glazed", reference(b, payloads[8]))};
    const auto textures =
        fb::CreateTexturesDirect(b, spec.textureWidth, spec.textureHeight, &regions, composed,
                                 &presets, spec.wrapU.value_or(false));
    flatbuffers::Offset<fb::Projector> camera;
    if (spec.camera) {
        const ProjectorCalibration& cam = *spec.camera;
        const fb::Mat3d cameraK(flatbuffers::make_span(cam.intrinsics));
        const fb::Mat3d cameraR(flatbuffers::make_span(cam.rotation));
        const fb::Distortion cameraKc(cam.distortion[0], cam.distortion[1], cam.distortion[2],
                                      cam.distortion[3], cam.distortion[4]);
        const fb::Vec3d cameraT(cam.translation[0], cam.translation[1], cam.translation[2]);
        camera = fb::CreateProjector(b, cam.width, cam.height, &cameraK, &cameraKc,
                                     spec.cameraWithoutRotation ? nullptr : &cameraR, &cameraT);
    }
    fb::FinishBundleBuffer(b,
                           fb::CreateBundle(b, mesh, projector, settings, model, textures, camera));
    return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
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

    std::vector<PlannedPayload> payloads;
    payloads.push_back(payload("positions", fb::ElementType::Float32, {4, 3}, bytesOf(positions)));
    payloads.push_back(payload("normals", fb::ElementType::Float32, {4, 3}, bytesOf(normals)));
    payloads.push_back(payload("uvs", fb::ElementType::Float32, {4, 2}, bytesOf(uvs)));
    payloads.push_back(payload("indices", fb::ElementType::UInt32, {2, 3}, bytesOf(indices)));
    const auto layers = static_cast<std::uint32_t>((coefficients + 3) / 4);
    payloads.push_back(halfLayers("region 0", layers, w, h));
    payloads.push_back(halfLayers("region 1", 1, w, h));
    payloads.push_back(halfLayers("composed", layers, w, h));
    payloads.push_back(payload("preset 0", fb::ElementType::UInt8, {2, h, w}, bytesOf(even)));
    payloads.push_back(payload("preset 1", fb::ElementType::Float16, {2, h, w}, bytesOf(glazed)));
    if (spec.detailNormals) {
        std::vector<std::uint16_t> detail(std::size_t{2} * w * h);
        for (std::size_t i = 0; i < detail.size(); ++i) {
            detail[i] = halfPattern(i);  // 0.125 … 0.5: inside the unit disc
        }
        payloads.push_back(
            payload("region 0 detail", fb::ElementType::Float16, {h, w, 2}, bytesOf(detail)));
    }

    BundleLayout layout;
    std::vector<std::span<const std::byte>> bytes;
    for (const PlannedPayload& p : payloads) {
        layout.add(p.record.type, p.record.shape);
        bytes.emplace_back(p.bytes);
    }
    // Every payload reference goes through the spec's hook, after layout, before the metadata.
    const std::vector<std::uint8_t> meta =
        layout.settle([&](const std::vector<PayloadPlacement>& placed) {
            std::vector<PlannedPayload> edited = payloads;
            for (std::size_t i = 0; i < edited.size(); ++i) {
                edited[i].record.offset = placed[i].offset;
                edited[i].record.size = placed[i].size;
                if (spec.editPayload) {
                    spec.editPayload(edited[i].name, edited[i].record);
                }
            }
            return metadata(spec, edited, coefficients);
        });
    return assembleBundle(layout, meta, bytes, spec.minorVersion);
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

std::filesystem::path writeBytes(const std::filesystem::path& path,
                                 const std::vector<std::byte>& bytes) {
    std::ofstream stream(path, std::ios::binary);
    stream.write(reinterpret_cast<const char*>(bytes.data()),
                 static_cast<std::streamsize>(bytes.size()));
    if (!stream) {
        throw std::runtime_error("cannot write " + path.string());
    }
    return path;
}

}  // namespace vpe::proto::testing
