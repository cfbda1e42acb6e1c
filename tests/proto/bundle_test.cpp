// SPDX-License-Identifier: MIT
// The device bundle reader: what it returns for a valid bundle, and the one-line refusal of
// every kind of bad file.
#include "vpe/proto/bundle.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>
#include <vector>

#include <gtest/gtest.h>

#include "bundle_fixture.h"
#include "test_paths.h"

namespace vpe::proto {
namespace {

using testing::buildRawBundle;
using testing::PayloadRecord;
using testing::RawBundleSpec;
using testing::resealChecksum;
using testing::ScratchFolder;
using testing::writeBytes;

// The message of the BundleError that opening `path` throws ("" if it opens).
std::string refusal(const std::filesystem::path& path, BundleOpenOptions options = {}) {
    try {
        BundleFile::open(path, options);
    } catch (const BundleError& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
        EXPECT_EQ(message, path.string() + ": " + error.problem());
        return message;
    }
    return "";
}

class BundleReader : public ::testing::Test {
protected:
    // Writes `bytes` as scene.vpeb and returns the message it is refused with.
    std::string refuse(const std::vector<std::byte>& bytes, BundleOpenOptions options = {}) {
        return refusal(writeBytes(path(), bytes), options);
    }
    std::filesystem::path path() const { return folder_ / "scene.vpeb"; }
    std::string prefix() const { return path().string() + ": "; }
    // The message a bundle whose model names the coefficient layout `layout` is refused with.
    std::string refuseLayout(const std::string& layout) {
        RawBundleSpec spec;
        spec.layout = layout;
        return refuse(buildRawBundle(spec));
    }

    ScratchFolder folder_;
};

template <typename T>
bool inside(std::span<const T> span, std::span<const std::byte> bytes) {
    const auto* begin = reinterpret_cast<const std::byte*>(span.data());
    return begin >= bytes.data() && begin + span.size_bytes() <= bytes.data() + bytes.size();
}

TEST_F(BundleReader, ReadsEveryFieldAndPointsIntoTheMapping) {
    const std::vector<std::byte> bytes = buildRawBundle();
    const BundleFile file = BundleFile::open(writeBytes(path(), bytes));
    const BundleView& view = file.view();
    EXPECT_TRUE(view.checksumVerified());
    EXPECT_EQ(view.header().majorVersion, kBundleMajorVersion);
    EXPECT_EQ(view.header().fileSize, bytes.size());
    EXPECT_EQ(view.bytes().size(), bytes.size());

    const MeshView& mesh = view.mesh();
    ASSERT_EQ(mesh.vertexCount(), 4u);
    ASSERT_EQ(mesh.triangleCount(), 2u);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        EXPECT_EQ(mesh.positions[i], testing::positionValue(i));
    }
    EXPECT_EQ(mesh.normals[2], 1.0f);
    EXPECT_EQ(mesh.uvs[6], 1.0f);
    EXPECT_EQ(mesh.indices[5], 3u);
    EXPECT_TRUE(inside(mesh.positions, view.bytes()));
    EXPECT_TRUE(inside(mesh.indices, view.bytes()));

    const ProjectorCalibration& p = view.projector();
    EXPECT_EQ(p.width, 1920u);
    EXPECT_EQ(p.height, 1080u);
    EXPECT_EQ(p.intrinsics[2], 960.0);
    EXPECT_EQ(p.distortion[4], 0.01);
    EXPECT_EQ(p.rotation[6], -1.0);
    EXPECT_EQ(p.translation[2], 1.5);

    const RenderSettings& s = view.settings();
    EXPECT_EQ(s.viewerPosition[2], 2.0f);
    EXPECT_EQ(s.screenAlbedo[1], 0.8f);
    EXPECT_EQ(s.ambientIrradiance[2], 0.03f);
    EXPECT_EQ(s.response.kind, ResponseKind::kGamma);
    EXPECT_EQ(s.response.gamma[1], 2.3f);
    EXPECT_EQ(s.peakIrradiance, 3.5f);
    EXPECT_EQ(s.gain, 0.8f);
    EXPECT_EQ(view.model().harmonics, 1);
    EXPECT_EQ(view.model().lambda, 3.14);

    EXPECT_EQ(view.textureWidth(), 4);
    EXPECT_EQ(view.textureHeight(), 2);
    ASSERT_EQ(view.regions().size(), 2u);
    const RegionView& base = view.regions()[0];
    EXPECT_EQ(base.name, "base");
    EXPECT_EQ(base.coefficients.encoding, CoefficientEncoding::kFull);
    EXPECT_EQ(base.coefficients.layers.layers, 3);  // 12 coefficients
    EXPECT_EQ(base.coefficients.bytesPerTexel(), 24);
    ASSERT_EQ(base.coefficients.layers.halves.size(), 3u * 2 * 4 * 4);
    for (std::size_t i = 0; i < base.coefficients.layers.halves.size(); ++i) {
        EXPECT_EQ(base.coefficients.layers.halves[i], testing::halfPattern(i));
    }
    EXPECT_TRUE(inside(base.coefficients.layers.halves, view.bytes()));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(base.coefficients.layers.halves.data()) % 64, 0u);
    const RegionView& glaze = view.regions()[1];
    EXPECT_EQ(glaze.name, "glaze");
    EXPECT_EQ(glaze.coefficients.encoding, CoefficientEncoding::kLowRank);
    EXPECT_EQ(glaze.coefficients.rank, 2);
    EXPECT_EQ(glaze.coefficients.layers.layers, 1);
    ASSERT_EQ(glaze.coefficients.mean.size(), 12u);
    EXPECT_EQ(glaze.coefficients.mean[3], 0.03f);
    ASSERT_EQ(glaze.coefficients.basis.size(), 24u);
    EXPECT_TRUE(inside(glaze.coefficients.basis, view.bytes()));
    ASSERT_TRUE(view.composed().has_value());
    EXPECT_EQ(view.composed()->encoding, CoefficientEncoding::kFull);

    ASSERT_EQ(view.presets().size(), 2u);
    const WeightPresetView& even = view.presets()[0];
    EXPECT_EQ(even.name, "even");
    EXPECT_EQ(even.encoding, AlphaEncoding::kUnorm8);
    ASSERT_EQ(even.unorm8.size(), 16u);
    EXPECT_EQ(even.unorm8[0] + even.unorm8[8], 255);
    EXPECT_EQ(even.bytesPerTexel(), 2);
    const WeightPresetView& glazed = view.presets()[1];
    EXPECT_EQ(glazed.encoding, AlphaEncoding::kFloat16);
    ASSERT_EQ(glazed.halves.size(), 16u);
    EXPECT_EQ(glazed.halves[8], 0x3c00);
    EXPECT_EQ(glazed.bytesPerTexel(), 4);
}

TEST_F(BundleReader, ReadsACurveResponse) {
    RawBundleSpec spec;
    spec.curveResponse = true;
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    const ResponseCurves& response = file->settings().response;
    EXPECT_EQ(response.kind, ResponseKind::kCurve);
    EXPECT_EQ(response.curve[0], spec.curve[0]);
    EXPECT_EQ(response.curve[2], spec.curve[2]);
}

TEST_F(BundleReader, ParsesFromMemoryAndMovesWithoutInvalidatingViews) {
    const std::vector<std::byte> bytes = buildRawBundle();
    // Any 64-byte aligned memory works, as a mapping does.
    auto* memory = static_cast<std::byte*>(::operator new (bytes.size(), std::align_val_t{64}));
    std::memcpy(memory, bytes.data(), bytes.size());
    const BundleView view = BundleView::parse({memory, bytes.size()}, "memory.vpeb");
    const auto* positions = reinterpret_cast<const std::byte*>(view.mesh().positions.data());
    EXPECT_GE(positions, memory + 64);
    EXPECT_EQ((positions - memory) % 64, 0);
    EXPECT_EQ(view.mesh().positions[1], testing::positionValue(1));
    ::operator delete (memory, std::align_val_t{64});

    BundleFile file = BundleFile::open(writeBytes(path(), bytes));
    const float* mapped = file->mesh().positions.data();
    BundleFile moved = std::move(file);
    EXPECT_EQ(moved->mesh().positions.data(), mapped);
    EXPECT_EQ(moved->mesh().positions[0], testing::positionValue(0));
}

TEST_F(BundleReader, ChecksumPassCanBeSkippedAndRunLater) {
    std::vector<std::byte> bytes = buildRawBundle();
    bytes.back() ^= std::byte{0x40};  // a preset's texel: structure intact
    BundleFile file = BundleFile::open(writeBytes(path(), bytes), {.verifyChecksum = false});
    EXPECT_FALSE(file->checksumVerified());
    EXPECT_THROW(file.view().verifyChecksum(), BundleError);
}

TEST_F(BundleReader, RefusesAMissingFile) {
    const std::filesystem::path missing = folder_ / "missing.vpeb";
    EXPECT_EQ(refusal(missing), missing.string() + ": cannot open: No such file or directory");
}

TEST_F(BundleReader, RefusesAFolder) {
    const std::filesystem::path folder = folder_ / "folder.vpeb";
    std::filesystem::create_directory(folder);
    EXPECT_EQ(refusal(folder), folder.string() + ": not a regular file");
}

TEST_F(BundleReader, RefusesAnEmptyFile) {
    EXPECT_EQ(refuse({}), prefix() + "empty file");
}

TEST_F(BundleReader, RefusesATruncatedFileWhereverItIsCut) {
    const std::vector<std::byte> bytes = buildRawBundle();
    const std::string total = std::to_string(bytes.size());
    const auto cut = [&](std::size_t size) {
        return refuse(std::vector<std::byte>(bytes.begin(), bytes.begin() + size));
    };
    EXPECT_EQ(cut(3), prefix() + "truncated: 3 bytes, shorter than the 64-byte header");
    EXPECT_EQ(cut(40), prefix() + "truncated: 40 bytes, shorter than the 64-byte header");
    for (std::size_t size :
         {std::size_t{64}, std::size_t{200}, bytes.size() / 2, bytes.size() - 1}) {
        EXPECT_EQ(cut(size), prefix() + "truncated: header says " + total + " bytes, file has " +
                                 std::to_string(size));
    }
}

TEST_F(BundleReader, RefusesTrailingBytes) {
    std::vector<std::byte> bytes = buildRawBundle();
    bytes.resize(bytes.size() + 10);
    EXPECT_EQ(refuse(bytes), prefix() + "wrong length: header says " +
                                 std::to_string(bytes.size() - 10) + " bytes, file has " +
                                 std::to_string(bytes.size()));
}

TEST_F(BundleReader, RefusesAFlippedByte) {
    const std::vector<std::byte> good = buildRawBundle();
    const std::uint32_t stored = BundleFile::open(writeBytes(path(), good))->header().checksum;
    for (std::size_t at : {std::size_t{64}, std::size_t{100}, good.size() - 1}) {
        std::vector<std::byte> bytes = good;
        bytes[at] ^= std::byte{1};
        char expected[128];
        std::snprintf(expected, sizeof expected,
                      "checksum mismatch: header says 0x%08x, contents give 0x%08x", stored,
                      bundleChecksum(std::span<const std::byte>(bytes).subspan(64)));
        EXPECT_EQ(refuse(bytes), prefix() + expected) << "byte " << at;
    }
}

TEST_F(BundleReader, RefusesAnotherKindOfFile) {
    std::vector<std::byte> bytes = buildRawBundle();
    const char zip[] = "PK\x03\x04";
    std::memcpy(bytes.data(), zip, 4);
    EXPECT_EQ(refuse(bytes), prefix() + "not a vpe bundle: starts with 'PK\\x03\\x04', not 'VPEB'");
    EXPECT_EQ(refuse({std::byte{'V'}, std::byte{'X'}}),
              prefix() + "not a vpe bundle: starts with 'VX', not 'VPEB'");
}

TEST_F(BundleReader, RefusesAnotherMajorVersionAndAcceptsANewerMinor) {
    std::vector<std::byte> bytes = buildRawBundle();
    const std::uint16_t version[2] = {2, 0};
    std::memcpy(bytes.data() + 4, version, sizeof version);
    EXPECT_EQ(refuse(bytes), prefix() + "format version 2.0, this reader supports 1.x");
    // Even when the rest is something this reader cannot make sense of.
    EXPECT_EQ(refuse(std::vector<std::byte>(bytes.begin(), bytes.begin() + 8)),
              prefix() + "format version 2.0, this reader supports 1.x");

    const std::uint16_t minor[2] = {1, 7};
    std::memcpy(bytes.data() + 4, minor, sizeof minor);
    EXPECT_EQ(refuse(bytes), "");
}

TEST_F(BundleReader, RefusesMetadataThatIsNotABundleFlatBuffer) {
    std::vector<std::byte> bytes = buildRawBundle();
    bytes[64 + 4] = std::byte{'X'};  // the file identifier "VPEM"
    resealChecksum(bytes);
    EXPECT_EQ(refuse(bytes),
              prefix() + "metadata is not a valid bundle FlatBuffer (identifier 'VPEM')");

    bytes = buildRawBundle();
    const std::uint64_t beyond = bytes.size();
    std::memcpy(bytes.data() + 24, &beyond, sizeof beyond);  // metadata size
    EXPECT_EQ(refuse(bytes), prefix() + "metadata of " + std::to_string(beyond) +
                                 " bytes at offset 64 does not fit in the file (" +
                                 std::to_string(bytes.size()) + " bytes)");
}

// A bundle whose payload `name` the hook changed, and the message it is refused with.
class PayloadReference : public BundleReader {
protected:
    std::string refuseEdited(const std::string& name,
                             const std::function<void(PayloadRecord&)>& edit) {
        RawBundleSpec spec;
        spec.editPayload = [&](const std::string& payload, PayloadRecord& record) {
            if (payload == name) {
                edit(record);
            }
        };
        bytes_ = buildRawBundle(spec);
        return refuse(bytes_);
    }
    std::vector<std::byte> bytes_;
};

TEST_F(PayloadReference, RefusesAnOffsetPastTheEnd) {
    std::uint64_t offset = 0;
    const std::string message = refuseEdited("region 0", [&](PayloadRecord& r) {
        r.offset += 1 << 20;
        offset = r.offset;
    });
    EXPECT_EQ(message, prefix() +
                           "region 0 'base' coefficients layers: payload of 192 bytes at "
                           "offset " +
                           std::to_string(offset) + " runs past the end of the file (" +
                           std::to_string(bytes_.size()) + " bytes)");
    EXPECT_NE(refuseEdited("indices", [](PayloadRecord& r) { r.offset = UINT64_MAX - 63; }), "");
}

TEST_F(PayloadReference, RefusesAPayloadOverlappingTheMetadata) {
    const std::string message = refuseEdited("positions", [](PayloadRecord& r) { r.offset = 64; });
    EXPECT_TRUE(message.starts_with(prefix() + "mesh positions: payload at offset 64 overlaps the "
                                               "header or metadata (they end at "))
        << message;
}

TEST_F(PayloadReference, RefusesAMisalignedPayload) {
    std::uint64_t offset = 0;
    const std::string message = refuseEdited("preset 1", [&](PayloadRecord& r) {
        r.offset += 8;
        offset = r.offset;
    });
    EXPECT_EQ(message, prefix() + "preset 1 'glazed' alpha: payload at offset " +
                           std::to_string(offset) + " is not 64-byte aligned");
}

TEST_F(PayloadReference, RefusesAWrongSize) {
    EXPECT_EQ(refuseEdited("region 1", [](PayloadRecord& r) { r.size -= 2; }),
              prefix() +
                  "region 1 'glaze' coefficients weights: 62 bytes, shape [1, 2, 4, 4] "
                  "of float16 needs 64");
    EXPECT_EQ(refuseEdited("uvs", [](PayloadRecord& r) { r.size = 0; }),
              prefix() + "mesh uvs: 0 bytes, shape [4, 2] of float32 needs 32");
}

TEST_F(PayloadReference, RefusesAWrongShapeOrElementType) {
    EXPECT_EQ(refuseEdited("normals",
                           [](PayloadRecord& r) {
                               r.shape = {3, 3};
                           }),
              prefix() + "mesh normals: shape [3, 3], expected [4, 3]");
    EXPECT_EQ(refuseEdited("positions", [](PayloadRecord& r) { r.shape = {12}; }),
              prefix() + "mesh positions: shape [12], expected [vertices, 3]");
    EXPECT_EQ(refuseEdited("composed",
                           [](PayloadRecord& r) {
                               r.shape = {3, 2, 4, 3};
                           }),
              prefix() + "composed coefficients layers: shape [3, 2, 4, 3], expected [3, 2, 4, 4]");
    EXPECT_EQ(refuseEdited("preset 0", [](PayloadRecord& r) { r.type = fb::ElementType::UInt32; }),
              prefix() + "preset 0 'even' alpha: element type uint32, expected uint8 or float16");
    EXPECT_EQ(
        refuseEdited("indices", [](PayloadRecord& r) { r.type = static_cast<fb::ElementType>(9); }),
        prefix() + "mesh indices: element type unknown type 9, expected uint32");
}

TEST_F(BundleReader, RefusesTexturesLargerThanTheDeviceCanUpload) {
    RawBundleSpec spec;
    spec.textureWidth = 8192;
    spec.textureHeight = 1;
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() +
                  "textures: 8192 x 1 exceeds the 4096 x 4096 limit of GLES 3.1 on the "
                  "Raspberry Pi");
    spec.textureWidth = 4096;
    EXPECT_EQ(refuse(buildRawBundle(spec)), "");
}

TEST_F(BundleReader, RefusesANonMonotoneResponseCurve) {
    RawBundleSpec spec;
    spec.curveResponse = true;
    spec.curve[1] = {0.0f, 0.5f, 0.4f, 1.0f};
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() +
                  "response curve green is not monotone: sample 2 (0.400000006) is below "
                  "sample 1 (0.5)");
    spec.curve[1] = {0.5f, 0.5f};
    EXPECT_EQ(refuse(buildRawBundle(spec)), prefix() + "response curve green is flat");
    spec.curve[1] = {0.5f};
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "response curve green has 1 samples, needs at least 2");
}

TEST_F(BundleReader, RefusesAnIndexPastTheVertices) {
    RawBundleSpec spec;
    spec.triangleIndexOverride = 4;
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "mesh indices: triangle 0 refers to vertex 4, there are 4");
}

TEST_F(BundleReader, RefusesAnUnknownCoefficientLayout) {
    EXPECT_EQ(refuseLayout("channel_major"),
              prefix() +
                  "model: coefficient layout 'channel_major', this reader knows "
                  "'fourier_brdf:k_major_rgb'");
}

// √(2/π)·cos θs and √(2/π)/√2: orthonormal over [0, π] at M = 1 (n = 3).
const float kUnit = static_cast<float>(std::sqrt(2.0 / 3.14159265358979323846));
const std::vector<float> kThetaBasis{0.0f, kUnit, 0.0f, kUnit, 0.0f, 0.0f};

TEST_F(BundleReader, ReadsAThetaBasis) {
    RawBundleSpec spec;
    spec.thetaBasis = kThetaBasis;
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_EQ(file->header().minorVersion, kBundleMinorVersion);
    EXPECT_EQ(file->model().thetaBasis, kThetaBasis);
    EXPECT_EQ(file->model().thetaBasisSize(), 2);
}

TEST_F(BundleReader, ReadsNoThetaBasisAsNone) {
    // Absent (as every 1.0 bundle) or empty: none, rendered exactly.
    RawBundleSpec spec;
    EXPECT_TRUE(
        BundleFile::open(writeBytes(path(), buildRawBundle(spec)))->model().thetaBasis.empty());
    spec.thetaBasis = std::vector<float>{};
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_TRUE(file->model().thetaBasis.empty());
    EXPECT_EQ(file->model().thetaBasisSize(), 0);
}

TEST_F(BundleReader, ReadsWhetherTexturesWrapInU) {
    // Absent (every 1.0 and 1.1 bundle) or false: clamped; true: sampling wraps in u.
    RawBundleSpec spec;
    EXPECT_FALSE(BundleFile::open(writeBytes(path(), buildRawBundle(spec)))->textureWrapsU());
    spec.wrapU = false;
    EXPECT_FALSE(BundleFile::open(writeBytes(path(), buildRawBundle(spec)))->textureWrapsU());
    spec.wrapU = true;
    EXPECT_TRUE(BundleFile::open(writeBytes(path(), buildRawBundle(spec)))->textureWrapsU());
}

TEST_F(BundleReader, ReadsAFormat10Bundle) {
    RawBundleSpec spec;
    spec.minorVersion = 0;
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_EQ(file->header().minorVersion, 0);
    EXPECT_TRUE(file->model().thetaBasis.empty());
    EXPECT_EQ(file->regions().size(), 2u);
}

TEST_F(BundleReader, ReadsADetailNormalMap) {
    RawBundleSpec spec;
    spec.detailNormals = true;
    const std::vector<std::byte> bytes = buildRawBundle(spec);
    const BundleFile file = BundleFile::open(writeBytes(path(), bytes));
    EXPECT_EQ(file->header().minorVersion, kBundleMinorVersion);
    const CoefficientMapView& base = file->regions()[0].coefficients;
    ASSERT_EQ(base.detailNormals.size(), 2u * 4 * 2);
    for (std::size_t i = 0; i < base.detailNormals.size(); ++i) {
        EXPECT_EQ(base.detailNormals[i], testing::halfPattern(i));
    }
    EXPECT_TRUE(inside(base.detailNormals, file->bytes()));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(base.detailNormals.data()) % 64, 0u);
    EXPECT_EQ(base.bytesPerTexel(), 24);  // the coefficients alone
    EXPECT_TRUE(file->regions()[1].coefficients.detailNormals.empty());
    ASSERT_TRUE(file->composed().has_value());
    EXPECT_TRUE(file->composed()->detailNormals.empty());
}

TEST_F(BundleReader, ReadsAFormat11BundleAsWithoutRelief) {
    RawBundleSpec spec;
    spec.minorVersion = 1;
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_EQ(file->header().minorVersion, 1);
    for (const RegionView& region : file->regions()) {
        EXPECT_TRUE(region.coefficients.detailNormals.empty());
    }
}

TEST_F(BundleReader, RefusesADetailNormalMapOfAnotherShapeOrType) {
    RawBundleSpec spec;
    spec.detailNormals = true;
    spec.editPayload = [](const std::string& name, PayloadRecord& record) {
        if (name == "region 0 detail") {
            record.shape = {2, 4, 3};
        }
    };
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() +
                  "region 0 'base' coefficients detail normals: shape [2, 4, 3], expected "
                  "[2, 4, 2]");
    spec.editPayload = [](const std::string& name, PayloadRecord& record) {
        if (name == "region 0 detail") {
            record.type = fb::ElementType::Float32;
        }
    };
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() +
                  "region 0 'base' coefficients detail normals: element type float32, "
                  "expected float16");
}

// A camera above the object looking down at it (R: 90° about x), distorted, at 1640 x 1232.
ProjectorCalibration testCamera() {
    ProjectorCalibration camera;
    camera.width = 1640;
    camera.height = 1232;
    camera.intrinsics = {1250, 0.5, 819.5, 0, 1252, 615.5, 0, 0, 1};
    camera.distortion = {-0.12, 0.08, 0.0004, -0.0003, -0.01};
    camera.rotation = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    camera.translation = {0.02, -0.1, 2.4};
    return camera;
}

TEST_F(BundleReader, ReadsTheInstallationsCamera) {
    RawBundleSpec spec;
    spec.camera = testCamera();
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_EQ(file->header().minorVersion, kBundleMinorVersion);
    ASSERT_TRUE(file->camera().has_value());
    const ProjectorCalibration& camera = *file->camera();
    EXPECT_EQ(camera.width, 1640u);
    EXPECT_EQ(camera.height, 1232u);
    EXPECT_EQ(camera.intrinsics, testCamera().intrinsics);
    EXPECT_EQ(camera.distortion, testCamera().distortion);
    EXPECT_EQ(camera.rotation, testCamera().rotation);
    EXPECT_EQ(camera.translation, testCamera().translation);
    // The projector is its own table, unchanged by the camera beside it.
    EXPECT_EQ(file->projector().width, 1920u);
    EXPECT_EQ(file->projector().translation[2], 1.5);
}

TEST_F(BundleReader, ReadsNoCameraAsNone) {
    // Absent: every bundle before 1.3, and a 1.3 bundle baked without one.
    EXPECT_FALSE(BundleFile::open(writeBytes(path(), buildRawBundle()))->camera().has_value());
}

TEST_F(BundleReader, ReadsAFormat12BundleWithoutCamera) {
    RawBundleSpec spec;
    spec.minorVersion = 2;
    spec.detailNormals = true;
    spec.wrapU = true;
    const BundleFile file = BundleFile::open(writeBytes(path(), buildRawBundle(spec)));
    EXPECT_EQ(file->header().minorVersion, 2);
    EXPECT_FALSE(file->camera().has_value());
    EXPECT_TRUE(file->textureWrapsU());
    EXPECT_FALSE(file->regions()[0].coefficients.detailNormals.empty());
    EXPECT_EQ(file->projector().width, 1920u);
}

TEST_F(BundleReader, RefusesABadCameraNamingIt) {
    RawBundleSpec spec;
    spec.camera = testCamera();
    spec.camera->intrinsics[4] = -1252;
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "camera intrinsics: focal lengths 1250, -1252 are not positive");
    spec.camera = testCamera();
    spec.camera->rotation[0] = -1;  // a mirror
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "camera rotation is a reflection (determinant -1)");
    spec.camera = testCamera();
    spec.camera->rotation[1] = 0.5;
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "camera rotation is not orthonormal (row 0 · row 0 = 1.25)");
    spec.camera = testCamera();
    spec.camera->height = 0;
    EXPECT_EQ(refuse(buildRawBundle(spec)), prefix() + "camera resolution 1640 x 0 is empty");
    spec.camera = testCamera();
    spec.camera->translation[1] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "camera calibration has a value that is not finite");
    spec.camera = testCamera();
    spec.cameraWithoutRotation = true;
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "camera: intrinsics, distortion, rotation or translation missing");
}

TEST(BundleSeeds, TheFuzzerSeedsWrittenIn10StillRead) {
    // tests/fuzz/corpus/bundle_fuzzer: bundles written by the 1.0 writer, checked in.
    int seeds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(
             std::filesystem::path(test_paths::sourceDir()) / "tests/fuzz/corpus/bundle_fuzzer")) {
        if (entry.path().extension() != ".vpeb") {
            continue;
        }
        ++seeds;
        const BundleFile file = BundleFile::open(entry.path());
        EXPECT_EQ(file->header().minorVersion, 0) << entry.path();
        EXPECT_TRUE(file->model().thetaBasis.empty()) << entry.path();
    }
    EXPECT_GE(seeds, 3);
}

TEST_F(BundleReader, RefusesABadThetaBasis) {
    RawBundleSpec spec;
    spec.thetaBasis = kThetaBasis;
    (*spec.thetaBasis)[1] = 1.0f;  // cos θs unscaled: norm² π/2
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() +
                  "model.theta_basis: functions 0 and 0 are not orthonormal over [0, π] (inner "
                  "product 1.570796)");
    spec.thetaBasis = kThetaBasis;
    (*spec.thetaBasis)[2] = 0.5f;  // a sin θs part, which cos θs and 1/√2 are not orthogonal to
    EXPECT_TRUE(refuse(buildRawBundle(spec))
                    .starts_with(prefix() + "model.theta_basis: functions 0 and 0 are not "
                                            "orthonormal over [0, π]"));
    spec.thetaBasis = std::vector<float>(kThetaBasis.begin(), kThetaBasis.begin() + 4);
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "model.theta_basis: 4 values, not a positive multiple of 2M + 1 = 3");
    spec.thetaBasis = std::vector<float>(12, 0.0f);
    EXPECT_EQ(refuse(buildRawBundle(spec)),
              prefix() + "model.theta_basis: 4 functions, more than 2M + 1 = 3");
    spec.thetaBasis = kThetaBasis;
    (*spec.thetaBasis)[4] = std::numeric_limits<float>::infinity();
    EXPECT_EQ(refuse(buildRawBundle(spec)), prefix() + "model.theta_basis: a value is not finite");
}

TEST_F(BundleReader, KeepsMessagesOnOneLineWhateverTheFileSays) {
    // Found by the fuzzer: text from the file goes into messages escaped.
    EXPECT_EQ(refuseLayout("fourier_\nbrdf\\"),
              prefix() +
                  "model: coefficient layout 'fourier_\\x0abrdf\\x5c', this reader knows "
                  "'fourier_brdf:k_major_rgb'");
}

TEST(BundleFormat, HeaderRoundTrips) {
    BundleHeader header;
    header.minorVersion = 3;
    header.flags = 0x10;
    header.checksum = 0xdeadbeef;
    header.metadataOffset = 64;
    header.metadataSize = 1234;
    header.fileSize = 1ull << 33;
    const BundleHeaderBytes bytes = encodeBundleHeader(header);
    std::vector<std::byte> file(bytes.begin(), bytes.end());
    try {
        decodeBundleHeader(file, "x");
        FAIL() << "a 64-byte file claiming 8 GiB was accepted";
    } catch (const BundleError& error) {
        EXPECT_EQ(error.problem(), "truncated: header says 8589934592 bytes, file has 64");
    }
    header.fileSize = 64;
    const BundleHeaderBytes exact = encodeBundleHeader(header);
    const BundleHeader decoded = decodeBundleHeader(exact, "x");
    EXPECT_EQ(decoded.minorVersion, 3);
    EXPECT_EQ(decoded.flags, 0x10u);
    EXPECT_EQ(decoded.checksum, 0xdeadbeefu);
    EXPECT_EQ(decoded.metadataSize, 1234u);
}

TEST(BundleFormat, ChecksumIsZlibCrc32AndStreams) {
    const char text[] = "123456789";
    const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(text), 9);
    EXPECT_EQ(bundleChecksum(bytes), 0xcbf43926u);  // the CRC-32 check value
    EXPECT_EQ(bundleChecksum(bytes.subspan(4), bundleChecksum(bytes.first(4))), 0xcbf43926u);
}

}  // namespace
}  // namespace vpe::proto
