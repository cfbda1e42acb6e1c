// SPDX-License-Identifier: MIT
// The GLES tests' vase, through the tests' one bundle builder (tests/support/test_bundle.h).
#include "gles_test_bundle.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#include <unistd.h>

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/bundle_generated.h"
#include "vpe/proto/bundle_layout.h"
#include "vpe/proto/half_float.h"
#include "vpe/proto/pinhole_camera.h"

#include "../support/test_bundle.h"
#include "test_scenes.h"

namespace vpe::renderer::testing {

namespace fb = proto::fb;

namespace {

using vpe::testing::testPayload;
using vpe::testing::TestPayload;

// Calls visit(x, y, t) for each texel of a w × h texture, t = y · w + x.
template <typename Visit>
void forEachTexel(int w, int h, Visit&& visit) {
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            visit(x, y,
                  static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                      static_cast<std::size_t>(x));
        }
    }
}

proto::ProjectorCalibration calibrationOf(const proto::PinholeCamera& camera) {
    return {static_cast<std::uint32_t>(camera.width),
            static_cast<std::uint32_t>(camera.height),
            camera.K,
            camera.distortion,
            camera.R,
            camera.T};
}

}  // namespace

std::vector<std::byte> buildGlesTestBundle(const GlesBundleSpec& spec) {
    const OwnedMesh vase = makeVaseMesh(spec.vaseSegments, spec.vaseRings);
    std::vector<float> positions, normals, uvs;
    // Half a turn about y: (x, y, z) → (−x, y, −z).
    const float turn = spec.seamInFront ? -1.0f : 1.0f;
    for (std::size_t v = 0; v < vase.positions.size(); ++v) {
        positions.insert(positions.end(), {turn * vase.positions[v].x, vase.positions[v].y,
                                           turn * vase.positions[v].z});
        normals.insert(normals.end(),
                       {turn * vase.normals[v].x, vase.normals[v].y, turn * vase.normals[v].z});
        uvs.insert(uvs.end(), {vase.uvs[v].x, 1.0f - vase.uvs[v].y});  // the bundle's v is down
    }
    const auto vertices = static_cast<std::uint32_t>(vase.positions.size());
    const auto triangles = static_cast<std::uint32_t>(vase.indices.size() / 3);

    const int w = spec.textureWidth, h = spec.textureHeight;
    const std::size_t texels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    const int c = 3 * (2 * spec.harmonics + 2);
    const int groups = (c + 3) / 4;
    // Region 0: a smooth, varied full map; coefficient k of channel ch at texel (x, y).
    const auto base = [&](int x, int y, int k, int ch) {
        const double u = (x + 0.5) / w, v = (y + 0.5) / h;
        if (k == 0) {
            return 0.45 + 0.25 * std::sin(6.0 * u + ch) * std::cos(4.0 * v);
        }
        if (k == 1) {
            return 0.05 + 0.02 * ch;
        }
        return 0.12 / k * std::cos(3.0 * u * k + 2.0 * v + ch);
    };
    std::vector<std::uint16_t> full(static_cast<std::size_t>(groups) * texels * 4, 0);
    forEachTexel(w, h, [&](int x, int y, std::size_t t) {
        for (int i = 0; i < c; ++i) {
            full[(static_cast<std::size_t>(i / 4) * texels + t) * 4 +
                 static_cast<std::size_t>(i % 4)] =
                proto::floatToHalf(static_cast<float>(base(x, y, i / 3, i % 3)));
        }
    });
    // Region 1: low rank, μ + Σ w_r B_r.
    const int rank = spec.lowRank;
    std::vector<float> mean(static_cast<std::size_t>(c)), basis(static_cast<std::size_t>(rank * c));
    for (int i = 0; i < c; ++i) {
        const int k = i / 3, ch = i % 3;
        mean[static_cast<std::size_t>(i)] = k == 0
                                                ? 0.3f + 0.1f * static_cast<float>(ch)
                                                : (k == 1 ? 0.03f : 0.2f / static_cast<float>(k));
        for (int r = 0; r < rank; ++r) {
            basis[static_cast<std::size_t>(r * c + i)] =
                static_cast<float>(0.1 * std::sin(1.7 * i + 2.3 * r + 0.5));
        }
    }
    const int rankLayers = (rank + 3) / 4;
    std::vector<std::uint16_t> codes(static_cast<std::size_t>(rankLayers) * texels * 4, 0);
    forEachTexel(w, h, [&](int x, int y, std::size_t t) {
        for (int r = 0; r < rank; ++r) {
            const double value = std::cos(0.3 * x * (r + 1) - 0.4 * y + r);
            codes[(static_cast<std::size_t>(r / 4) * texels + t) * 4 +
                  static_cast<std::size_t>(r % 4)] = proto::floatToHalf(static_cast<float>(value));
        }
    });
    std::vector<std::uint8_t> stripes(2 * texels);
    std::vector<std::uint16_t> radial(2 * texels);
    forEachTexel(w, h, [&](int x, int y, std::size_t t) {
        const auto a = static_cast<std::uint8_t>(std::lround(127.5 + 127.5 * std::sin(0.5 * x)));
        stripes[t] = a;
        stripes[texels + t] = static_cast<std::uint8_t>(255 - a);
        const double d = std::hypot(x - 0.5 * w, y - 0.5 * h) / (0.5 * w);
        const float alpha = static_cast<float>(std::clamp(1.0 - d, 0.0, 1.0));
        radial[t] = proto::floatToHalf(alpha);
        radial[texels + t] = proto::floatToHalf(1.0f - alpha);
    });

    std::vector<TestPayload> payloads;
    payloads.push_back(
        testPayload("positions", fb::ElementType::Float32, {vertices, 3}, positions));
    payloads.push_back(testPayload("normals", fb::ElementType::Float32, {vertices, 3}, normals));
    payloads.push_back(testPayload("uvs", fb::ElementType::Float32, {vertices, 2}, uvs));
    payloads.push_back(
        testPayload("indices", fb::ElementType::UInt32, {triangles, 3}, vase.indices));
    const auto uw = static_cast<std::uint32_t>(w), uh = static_cast<std::uint32_t>(h);
    payloads.push_back(testPayload("region 0", fb::ElementType::Float16,
                                   {static_cast<std::uint32_t>(groups), uh, uw, 4}, full));
    payloads.push_back(testPayload("region 1", fb::ElementType::Float16,
                                   {static_cast<std::uint32_t>(rankLayers), uh, uw, 4}, codes));
    payloads.push_back(testPayload("preset 0", fb::ElementType::UInt8, {2, uh, uw}, stripes));
    payloads.push_back(testPayload("preset 1", fb::ElementType::Float16, {2, uh, uw}, radial));
    if (spec.relief) {
        // Bumps across the texture: the detail normal's x and y, |(x, y)| ≤ 0.5.
        std::vector<std::uint16_t> detail(2 * texels);
        forEachTexel(w, h, [&](int x, int y, std::size_t t) {
            detail[2 * t] =
                proto::floatToHalf(static_cast<float>(0.35 * std::sin(0.9 * x + 0.4 * y)));
            detail[2 * t + 1] =
                proto::floatToHalf(static_cast<float>(0.35 * std::cos(0.7 * y - 0.5 * x)));
        });
        payloads.push_back(
            testPayload("region 0 detail", fb::ElementType::Float16, {uh, uw, 2}, detail));
    }

    if (spec.measuredLight) {
        const auto pw = static_cast<std::uint32_t>(spec.projectorWidth);
        const auto ph = static_cast<std::uint32_t>(spec.projectorHeight);
        std::vector<std::uint16_t> irradiance(std::size_t{pw} * ph * 4, 0),
            floor(irradiance.size(), 0);
        for (std::uint32_t y = 0; y < ph; ++y) {
            for (std::uint32_t x = 0; x < pw; ++x) {
                const std::size_t p = std::size_t{y} * pw + x;
                const double u = double(x) / pw, v = double(y) / ph;
                const double stain =
                    1.0 - 0.3 * std::exp(-40 * ((u - 0.4) * (u - 0.4) + (v - 0.5) * (v - 0.5)));
                const double corner = 0.8 + 0.4 * u * v;
                const double f[3] = {0.9 * stain * corner, 0.8 * stain * corner, 0.7 * corner};
                for (std::size_t k = 0; k < 3; ++k) {
                    irradiance[4 * p + k] = proto::floatToHalf(static_cast<float>(f[k]));
                    floor[4 * p + k] = proto::floatToHalf(static_cast<float>(0.012 * f[k] + 0.004));
                }
            }
        }
        payloads.push_back(
            testPayload("irradiance", fb::ElementType::Float16, {ph, pw, 4}, irradiance));
        payloads.push_back(testPayload("floor", fb::ElementType::Float16, {ph, pw, 4}, floor));
    }

    proto::PinholeCamera camera = proto::cameraLookingAt(
        spec.projectorWidth, spec.projectorHeight, 38.0, {0.08, 0.11, 0.42}, {0.0, 0.075, 0.0});
    if (spec.distortion) {
        camera.distortion = spec.distortionCoefficients;
    }

    const auto bundleTable = [&](flatbuffers::FlatBufferBuilder& b,
                                 const std::vector<proto::PayloadPlacement>& placed) {
        const auto ref = [&](std::size_t i) { return proto::payloadReference(b, placed[i]); };
        const auto mesh = fb::CreateMesh(b, ref(0), ref(1), ref(2), ref(3));
        const auto projector = vpe::testing::projectorTable(b, calibrationOf(camera));
        const std::array<std::vector<float>, 3> curve{{{0.02f, 0.1f, 0.3f, 0.6f, 1.0f},
                                                       {0.0f, 0.2f, 0.45f, 0.7f, 0.9f, 1.1f},
                                                       {0.01f, 0.5f, 1.0f}}};
        const vpe::testing::ResponseTable response =
            vpe::testing::responseTable(b, spec.curveResponse ? &curve : nullptr);
        const fb::Vec3f viewer(0.3f, 0.2f, 0.6f);
        const fb::Rgb albedo(0.85f, 0.8f, 0.75f);
        const fb::Rgb ambient(0.01f, 0.02f, 0.03f);
        const auto settings = fb::CreateRenderSettings(b, &viewer, &albedo, &ambient, response.kind,
                                                       response.table, 0.8f, 1.0f);
        const auto model = fb::CreateModelDirect(b, static_cast<std::uint16_t>(spec.harmonics),
                                                 3.14, "fourier_brdf:k_major_rgb");
        const auto detail = spec.relief ? ref(8) : flatbuffers::Offset<fb::Payload>();
        const auto fullMap =
            fb::CreateCoefficientMap(b, fb::CoefficientEncoding::FullCoefficients,
                                     fb::CreateFullCoefficients(b, ref(4)).Union(), detail);
        const auto lowRankMap =
            fb::CreateCoefficientMap(b, fb::CoefficientEncoding::LowRankCoefficients,
                                     fb::CreateLowRankCoefficientsDirect(
                                         b, static_cast<std::uint16_t>(rank), &mean, &basis, ref(5))
                                         .Union());
        std::vector<flatbuffers::Offset<fb::Region>> regions{
            fb::CreateRegionDirect(b, "base", fullMap),
            fb::CreateRegionDirect(b, "glaze", lowRankMap)};
        std::vector<flatbuffers::Offset<fb::WeightPreset>> presets{
            fb::CreateWeightPresetDirect(b, "stripes", ref(6)),
            fb::CreateWeightPresetDirect(b, "radial", ref(7))};
        const auto textures =
            fb::CreateTexturesDirect(b, uw, uh, &regions, 0, &presets, spec.wrapU);
        flatbuffers::Offset<fb::Projector> installationCamera;
        if (spec.camera) {
            installationCamera = vpe::testing::projectorTable(b, calibrationOf(*spec.camera));
        }
        flatbuffers::Offset<fb::Radiometry> radiometry;
        if (spec.measuredLight) {
            const std::size_t first = placed.size() - 2;
            const std::array<double, 9> mixing{1, 0.076, 0.011, 0.068, 1, 0.057, 0.011, 0.097, 1};
            const fb::Mat3d x(flatbuffers::make_span(mixing));
            radiometry = fb::CreateRadiometry(b, &x, ref(first), ref(first + 1));
        }
        return fb::CreateBundle(b, mesh, projector, settings, model, textures, installationCamera,
                                radiometry);
    };
    vpe::testing::TestBundleSpec bundle;
    bundle.payloads = std::move(payloads);
    bundle.bundleTable = bundleTable;
    return vpe::testing::buildTestBundle(bundle);
}

std::filesystem::path MappedTestBundle::write(const GlesBundleSpec& spec) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "vpe-gles-XXXXXX.vpeb").string();
    const int fd = ::mkstemps(pattern.data(), 5);
    if (fd < 0) {
        throw std::runtime_error("cannot create a temporary bundle");
    }
    ::close(fd);
    return vpe::testing::writeBytes(pattern, buildGlesTestBundle(spec));
}

MappedTestBundle::MappedTestBundle(const GlesBundleSpec& spec)
    : path_(write(spec)), file_(proto::BundleFile::open(path_)) {}

MappedTestBundle::~MappedTestBundle() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
}

}  // namespace vpe::renderer::testing
