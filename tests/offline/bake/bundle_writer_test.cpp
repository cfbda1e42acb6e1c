// SPDX-License-Identifier: MIT
// The bundle writer: everything it is given comes back through the device reader, encoded as
// documented (half floats, packed layers, 8-bit weights adding up to 255); contents a device
// would refuse are refused before anything is left on disk.
#include "vpe/bake/bundle_writer.h"

#include <cmath>
#include <fstream>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/half_float.h"

#include "offline/bake/bundle_sample.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using bake::BundleContents;
using proto::BundleFile;

float fromHalf(std::uint16_t bits) {
    return static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(bits));
}

// Half floats keep 11 significant bits.
void expectHalfOf(std::uint16_t bits, float expected, const std::string& where) {
    EXPECT_NEAR(fromHalf(bits), expected, std::fabs(expected) / 1024 + 1e-7f) << where;
}

// The packed value i of texel t: layer i / 4, component i % 4.
std::uint16_t packedValue(const proto::HalfLayers& layers, std::size_t t, std::size_t i) {
    const std::size_t texels = static_cast<std::size_t>(layers.width) * layers.height;
    return layers.halves[((i / 4) * texels + t) * 4 + i % 4];
}

// Neither the output nor a temporary file beside it.
void expectNothingWritten(const std::filesystem::path& folder) {
    EXPECT_TRUE(std::filesystem::is_empty(folder)) << "left behind in " << folder;
}

class BundleWriter : public ::testing::Test {
protected:
    std::filesystem::path path() const { return folder_ / "scene.vpeb"; }
    // The InputError message writing `contents` throws ("" if it writes).
    std::string refusal(const BundleContents& contents) {
        try {
            bake::writeBundle(path(), contents);
        } catch (const common::InputError& error) {
            return error.what();
        }
        return "";
    }
    testing::TemporaryFolder folder_;
    BundleContents contents_ = testing::sampleBundleContents();
};

TEST_F(BundleWriter, RoundTripsEveryField) {
    const bake::BundleWriteResult result = bake::writeBundle(path(), contents_);
    EXPECT_EQ(result.bytes, std::filesystem::file_size(path()));
    const BundleFile file = BundleFile::open(path());
    const proto::BundleView& view = file.view();
    EXPECT_EQ(view.header().checksum, result.checksum);
    EXPECT_EQ(view.header().majorVersion, proto::kBundleMajorVersion);
    EXPECT_EQ(view.header().minorVersion, proto::kBundleMinorVersion);
    EXPECT_EQ(view.header().metadataOffset, 64u);

    const proto::MeshView& mesh = view.mesh();
    const bake::BundleMesh& m = contents_.mesh;
    EXPECT_EQ(std::vector<float>(mesh.positions.begin(), mesh.positions.end()), m.positions);
    EXPECT_EQ(std::vector<float>(mesh.normals.begin(), mesh.normals.end()), m.normals);
    EXPECT_EQ(std::vector<float>(mesh.uvs.begin(), mesh.uvs.end()), m.uvs);
    EXPECT_EQ(std::vector<std::uint32_t>(mesh.indices.begin(), mesh.indices.end()), m.indices);

    const proto::ProjectorCalibration& p = view.projector();
    EXPECT_EQ(p.width, contents_.projector.width);
    EXPECT_EQ(p.height, contents_.projector.height);
    EXPECT_EQ(p.intrinsics, contents_.projector.intrinsics);
    EXPECT_EQ(p.distortion, contents_.projector.distortion);
    EXPECT_EQ(p.rotation, contents_.projector.rotation);
    EXPECT_EQ(p.translation, contents_.projector.translation);

    const proto::RenderSettings& s = view.settings();
    EXPECT_EQ(s.viewerPosition, contents_.settings.viewerPosition);
    EXPECT_EQ(s.screenAlbedo, contents_.settings.screenAlbedo);
    EXPECT_EQ(s.ambientIrradiance, contents_.settings.ambientIrradiance);
    EXPECT_EQ(s.response.kind, proto::ResponseKind::kCurve);
    EXPECT_EQ(s.response.curve, contents_.settings.response.curve);
    EXPECT_EQ(s.peakIrradiance, contents_.settings.peakIrradiance);
    EXPECT_EQ(s.gain, contents_.settings.gain);
    EXPECT_EQ(view.model().harmonics, 2);
    EXPECT_EQ(view.model().lambda, 0.5);
    EXPECT_EQ(view.model().thetaBasis, contents_.model.thetaBasis);
    EXPECT_EQ(view.model().thetaBasisSize(), 2);

    EXPECT_EQ(view.textureWidth(), 5);
    EXPECT_EQ(view.textureHeight(), 3);
    EXPECT_EQ(view.textureWrapsU(), contents_.textureWrapsU);
    const std::size_t texels = 15;
    const std::size_t values = 18;
    ASSERT_EQ(view.regions().size(), 2u);

    const proto::RegionView& base = view.regions()[0];
    EXPECT_EQ(base.name, "base");
    ASSERT_EQ(base.coefficients.encoding, proto::CoefficientEncoding::kFull);
    const proto::HalfLayers& layers = base.coefficients.layers;
    ASSERT_EQ(layers.layers, 5);
    ASSERT_EQ(layers.halves.size(), 5 * texels * 4);
    for (std::size_t t = 0; t < texels; ++t) {
        for (std::size_t i = 0; i < 20; ++i) {
            const std::string where = "texel " + std::to_string(t) + " value " + std::to_string(i);
            if (i < values) {
                expectHalfOf(packedValue(layers, t, i),
                             contents_.regions[0].coefficients.coefficients[t * values + i], where);
            } else {
                EXPECT_EQ(packedValue(layers, t, i), 0) << where << " (padding)";
            }
        }
    }

    const proto::RegionView& glaze = view.regions()[1];
    const bake::CoefficientMapData& lowRank = contents_.regions[1].coefficients;
    EXPECT_EQ(glaze.name, "glaze");
    ASSERT_EQ(glaze.coefficients.encoding, proto::CoefficientEncoding::kLowRank);
    EXPECT_EQ(glaze.coefficients.rank, 5);
    EXPECT_EQ(std::vector<float>(glaze.coefficients.mean.begin(), glaze.coefficients.mean.end()),
              lowRank.mean);
    EXPECT_EQ(std::vector<float>(glaze.coefficients.basis.begin(), glaze.coefficients.basis.end()),
              lowRank.basis);
    ASSERT_EQ(glaze.coefficients.layers.layers, 2);
    for (std::size_t t = 0; t < texels; ++t) {
        for (std::size_t r = 0; r < 8; ++r) {
            const std::uint16_t bits = packedValue(glaze.coefficients.layers, t, r);
            if (r < 5) {
                expectHalfOf(bits, lowRank.weights[t * 5 + r], "weight " + std::to_string(r));
            } else {
                EXPECT_EQ(bits, 0);
            }
        }
    }
    ASSERT_TRUE(view.composed().has_value());
    EXPECT_EQ(view.composed()->encoding, proto::CoefficientEncoding::kFull);
    EXPECT_EQ(view.composed()->layers.halves[7], layers.halves[7]);

    ASSERT_EQ(view.presets().size(), 2u);
    const proto::WeightPresetView& stripes = view.presets()[0];
    EXPECT_EQ(stripes.name, "stripes");
    ASSERT_EQ(stripes.encoding, proto::AlphaEncoding::kUnorm8);
    ASSERT_EQ(stripes.unorm8.size(), 2 * texels);
    for (std::size_t t = 0; t < texels; ++t) {
        EXPECT_EQ(stripes.unorm8[t] + stripes.unorm8[texels + t], 255) << "texel " << t;
        for (std::size_t k = 0; k < 2; ++k) {
            EXPECT_NEAR(stripes.unorm8[k * texels + t],
                        255 * contents_.presets[0].alpha[k * texels + t], 1.0);
        }
    }
    const proto::WeightPresetView& fade = view.presets()[1];
    EXPECT_EQ(fade.name, "fade");
    ASSERT_EQ(fade.encoding, proto::AlphaEncoding::kFloat16);
    ASSERT_EQ(fade.halves.size(), 2 * texels);
    for (std::size_t i = 0; i < fade.halves.size(); ++i) {
        expectHalfOf(fade.halves[i], contents_.presets[1].alpha[i], "alpha " + std::to_string(i));
    }
}

TEST_F(BundleWriter, WritesAGammaResponseAndNoComposedMapOrPresets) {
    contents_.settings.response = {};
    contents_.settings.response.gamma = {2.2f, 2.4f, 2.6f};
    contents_.composed.reset();
    contents_.presets.clear();
    bake::writeBundle(path(), contents_);
    const BundleFile file = BundleFile::open(path());
    EXPECT_EQ(file->settings().response.kind, proto::ResponseKind::kGamma);
    EXPECT_EQ(file->settings().response.gamma, contents_.settings.response.gamma);
    EXPECT_FALSE(file->composed().has_value());
    EXPECT_TRUE(file->presets().empty());
}

TEST_F(BundleWriter, WritesNoThetaBasisWhenThereIsNone) {
    contents_.model.thetaBasis.clear();
    bake::writeBundle(path(), contents_);
    const BundleFile file = BundleFile::open(path());
    EXPECT_TRUE(file->model().thetaBasis.empty());
    EXPECT_EQ(file->header().minorVersion, proto::kBundleMinorVersion);  // whatever it holds
}

// Format 1.6: the visitors' eyes a show is drawn for; at most 16, each finite.
TEST_F(BundleWriter, WritesAViewingZoneAndRefusesABadOne) {
    EXPECT_TRUE(BundleFile::open((bake::writeBundle(path(), contents_), path()))
                    ->settings()
                    .viewingZone.empty());
    contents_.settings.viewingZone = {{1.0f, 0.2f, 0.0f}, {-1.0f, 0.2f, 0.5f}};
    bake::writeBundle(path(), contents_);
    EXPECT_EQ(BundleFile::open(path())->settings().viewingZone, contents_.settings.viewingZone);
    contents_.settings.viewingZone.assign(17, {0.0f, 0.0f, 1.0f});
    EXPECT_EQ(refusal(contents_), path().string() + ": viewing zone has 17 eyes, more than 16");
    contents_.settings.viewingZone = {{0.0f, std::nanf(""), 1.0f}};
    EXPECT_EQ(refusal(contents_), path().string() + ": viewing zone: an eye is not finite");
}

TEST_F(BundleWriter, RefusesABadThetaBasis) {
    contents_.model.thetaBasis[1] = 1.0f;  // cos θs unscaled: norm² π/2
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": model.theta_basis: functions 0 and 0 are not "
                                      "orthonormal over [0, π] (inner product 1.570796)");
    contents_ = testing::sampleBundleContents();
    contents_.model.thetaBasis.pop_back();
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": model.theta_basis: 9 values, not a positive multiple of "
                                      "2M + 1 = 5");
    contents_ = testing::sampleBundleContents();
    contents_.model.thetaBasis[0] = std::nanf("");
    EXPECT_EQ(refusal(contents_), path().string() + ": model.theta_basis: a value is not finite");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, AlignsEveryPayload) {
    bake::writeBundle(path(), contents_);
    const BundleFile file = BundleFile::open(path());
    const auto offset = [&](const void* data) {
        return static_cast<const std::byte*>(data) - file->bytes().data();
    };
    EXPECT_EQ(offset(file->mesh().positions.data()) % 64, 0);
    EXPECT_EQ(offset(file->mesh().indices.data()) % 64, 0);
    EXPECT_EQ(offset(file->regions()[1].coefficients.layers.halves.data()) % 64, 0);
    EXPECT_EQ(offset(file->presets()[0].unorm8.data()) % 64, 0);
}

TEST_F(BundleWriter, RefusesTexturesLargerThan4096) {
    contents_.textureWidth = 4097;
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": textures: 4097 x 3 is outside 1..4096 "
                                      "(GLES 3.1 on the Raspberry Pi)");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, RefusesANonMonotoneResponseCurve) {
    contents_.settings.response.curve[2] = {0.0f, 0.6f, 0.5f, 1.0f};
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": response curve blue is not monotone: "
                                      "sample 2 (0.5) is below sample 1 "
                                      "(0.600000024)");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, RefusesWeightsThatDoNotSumToOne) {
    contents_.presets[1].alpha[3] += 0.01f;
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": preset 1 'fade' alpha: sums to 1.010000 "
                                      "at texel (3, 0), not 1");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, WritesAReliefAsHalfFloatsAndRefusesOneOffTheUnitDisc) {
    const std::size_t texels = static_cast<std::size_t>(contents_.textureWidth) *
                               static_cast<std::size_t>(contents_.textureHeight);
    std::vector<float>& detail = contents_.regions[1].coefficients.detailNormals;
    for (std::size_t i = 0; i < 2 * texels; ++i) {
        detail.push_back(0.25f * static_cast<float>(i % 3) - 0.25f);  // -0.25, 0, 0.25
    }
    bake::writeBundle(path(), contents_);
    {
        const BundleFile file = BundleFile::open(path());
        EXPECT_EQ(file->header().minorVersion, proto::kBundleMinorVersion);
        EXPECT_TRUE(file->regions()[0].coefficients.detailNormals.empty());
        const auto& read = file->regions()[1].coefficients.detailNormals;
        ASSERT_EQ(read.size(), detail.size());
        for (std::size_t i = 0; i < read.size(); ++i) {
            EXPECT_EQ(proto::halfToFloat(read[i]), detail[i]) << i;  // exact in half floats
        }
    }
    detail[3] = 0.9f;
    detail[2] = 0.5f;  // texel 1: (0.5, 0.9), off the unit disc
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": region 1 'glaze' coefficients detail normals: texel "
                                      "(1, 0) is (0.500000, 0.900000), not the x and y of a "
                                      "unit normal");
    detail.pop_back();
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": region 1 'glaze' coefficients detail normals: " +
                                      std::to_string(2 * texels - 1) + " values, expected " +
                                      std::to_string(2 * texels));
}

TEST_F(BundleWriter, RefusesValuesAHalfFloatCannotHold) {
    contents_.regions[0].coefficients.coefficients[40] = 70000.0f;
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": region 0 'base' coefficients: value 40 "
                                      "(70000.000000) does not fit a half float");
    contents_ = testing::sampleBundleContents();
    contents_.regions[1].coefficients.weights[2] = std::nanf("");
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": region 1 'glaze' coefficients weights: "
                                      "value 2 (nan) is not finite");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, RefusesInconsistentSizes) {
    contents_.mesh.uvs.pop_back();
    EXPECT_EQ(refusal(contents_), path().string() + ": mesh uvs: 7 values, expected 8");
    contents_ = testing::sampleBundleContents();
    contents_.mesh.indices[4] = 9;
    EXPECT_EQ(refusal(contents_),
              path().string() + ": mesh indices: triangle 1 refers to vertex 9, there are 4");
    contents_ = testing::sampleBundleContents();
    contents_.regions[1].coefficients.rank = 19;
    EXPECT_EQ(refusal(contents_),
              path().string() + ": region 1 'glaze' coefficients: rank 19 is outside 1..18");
    contents_ = testing::sampleBundleContents();
    contents_.presets[1].name = "stripes";
    EXPECT_EQ(refusal(contents_),
              path().string() + ": preset 1 'stripes': another preset has the same name");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, RefusesABadCalibration) {
    contents_.projector.rotation[0] = 2;
    EXPECT_EQ(refusal(contents_), path().string() +
                                      ": projector rotation is not orthonormal "
                                      "(row 0 · row 0 = 4)");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, WritesTheCameraWhenThereIsOneAndRefusesABadOne) {
    EXPECT_FALSE(
        (bake::writeBundle(path(), contents_), BundleFile::open(path())->camera().has_value()));
    proto::ProjectorCalibration camera;
    camera.width = 640;
    camera.height = 480;
    camera.intrinsics = {500.25, 0, 319.5, 0, 501, 239.5, 0, 0, 1};
    camera.distortion = {-0.1, 0.02, 0.001, -0.002, 0.003};
    camera.rotation = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    camera.translation = {0.1, 0.2, 2.5};
    contents_.camera = camera;
    bake::writeBundle(path(), contents_);
    {
        const BundleFile file = BundleFile::open(path());
        ASSERT_TRUE(file->camera().has_value());
        EXPECT_EQ(file->camera()->width, 640u);
        EXPECT_EQ(file->camera()->intrinsics, camera.intrinsics);
        EXPECT_EQ(file->camera()->distortion, camera.distortion);
        EXPECT_EQ(file->camera()->rotation, camera.rotation);
        EXPECT_EQ(file->camera()->translation, camera.translation);
    }
    std::filesystem::remove(path());
    contents_.camera->intrinsics[0] = 0;
    EXPECT_EQ(refusal(contents_),
              path().string() + ": camera intrinsics: focal lengths 0, 501 are not positive");
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, WritesTheMeasuredLightAndRefusesBadMaps) {
    EXPECT_FALSE(
        (bake::writeBundle(path(), contents_), BundleFile::open(path())->radiometry().has_value()));
    const std::size_t pixels =
        static_cast<std::size_t>(contents_.projector.width) * contents_.projector.height;
    bake::BundleRadiometry radiometry;
    radiometry.mixing = {1, 0.076, 0.011, 0.068, 1, 0.057, 0.011, 0.097, 1};
    for (std::size_t p = 0; p < pixels; ++p) {
        for (const float base : {0.25f, 0.5f, 0.75f}) {
            radiometry.irradiance.push_back(base + 0.001f * static_cast<float>(p % 7));
            radiometry.floor.push_back(0.01f * base);
        }
    }
    contents_.radiometry = radiometry;
    bake::writeBundle(path(), contents_);
    {
        const BundleFile file = BundleFile::open(path());
        ASSERT_TRUE(file->radiometry().has_value());
        EXPECT_EQ(file->radiometry()->mixing, radiometry.mixing);
        ASSERT_EQ(file->radiometry()->irradiance.size(), 4 * pixels);
        for (std::size_t p = 0; p < pixels; p += 97) {
            for (std::size_t c = 0; c < 3; ++c) {
                EXPECT_NEAR(proto::halfToFloat(file->radiometry()->irradiance[4 * p + c]),
                            radiometry.irradiance[3 * p + c], 5e-4);
                EXPECT_NEAR(proto::halfToFloat(file->radiometry()->floor[4 * p + c]),
                            radiometry.floor[3 * p + c], 1e-5);
            }
            EXPECT_EQ(file->radiometry()->irradiance[4 * p + 3], 0);
        }
    }
    std::filesystem::remove(path());
    contents_.radiometry->floor[5] = -0.5f;
    EXPECT_EQ(refusal(contents_),
              path().string() + ": radiometry: a map value outside [0, 65504] (half floats)");
    contents_.radiometry->floor[5] = 0;
    contents_.radiometry->mixing[4] = 0.9;
    EXPECT_EQ(refusal(contents_), path().string() + ": radiometry: mixing: its diagonal must be 1");
    contents_.radiometry->mixing[4] = 1;
    contents_.radiometry->irradiance.pop_back();
    EXPECT_NE(refusal(contents_).find("radiometry irradiance"), std::string::npos);
    expectNothingWritten(folder_.path());
}

TEST_F(BundleWriter, KeepsTheOldBundleWhenANewOneIsRefused) {
    bake::writeBundle(path(), contents_);
    const auto before = std::filesystem::file_size(path());
    contents_.textureHeight = 0;
    EXPECT_NE(refusal(contents_), "");
    EXPECT_EQ(std::filesystem::file_size(path()), before);
    EXPECT_NO_THROW(BundleFile::open(path()));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder_.path()),
                            std::filesystem::directory_iterator()),
              1);
}

}  // namespace
}  // namespace vpe
