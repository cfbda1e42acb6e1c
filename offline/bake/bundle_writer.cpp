// SPDX-License-Identifier: MIT
// The bundle writer: checks the contents, plans the payloads, builds the FlatBuffer metadata
// around their offsets, streams header, metadata and payloads with a running CRC-32, then
// proves the file with the device reader before renaming it into place.
#include "vpe/bake/bundle_writer.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numeric>
#include <set>
#include <stdexcept>

#include <unistd.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/bundle_generated.h"
#include "vpe/proto/bundle_layout.h"
#include "vpe/proto/half_float.h"

namespace vpe::bake {

namespace {

namespace fb = proto::fb;

// The largest finite half float.
constexpr float kHalfMax = 65504.0f;
// How far a preset's Σα may be from 1 before it is refused rather than normalized.
constexpr double kAlphaSumTolerance = 1e-3;

std::size_t texels(const BundleContents& c) {
    return static_cast<std::size_t>(c.textureWidth) * static_cast<std::size_t>(c.textureHeight);
}

// ---- checking the contents -------------------------------------------------------------

class ContentsCheck {
public:
    ContentsCheck(const std::filesystem::path& path, const BundleContents& contents)
        : path_(path), c_(contents) {}

    void run() {
        ruleFromProto(proto::checkProjector(c_.projector));
        if (c_.camera) {
            ruleFromProto(proto::checkBundleCamera(*c_.camera));
        }
        if (c_.radiometry) {
            radiometry(*c_.radiometry);
        }
        if (c_.blend) {
            blend(*c_.blend);
        }
        ruleFromProto(proto::checkSettings(c_.settings));
        ruleFromProto(proto::checkModel(c_.model));
        mesh();
        if (!proto::textureSizeFits(c_.textureWidth, c_.textureHeight)) {
            fail("textures: " + std::to_string(c_.textureWidth) + " x " +
                 std::to_string(c_.textureHeight) +
                 " is outside 1..4096 (GLES 3.1 on the "
                 "Raspberry Pi)");
        }
        if (!proto::regionCountFits(c_.regions.size())) {
            fail("textures: " + std::to_string(c_.regions.size()) + " regions, need 1..256");
        }
        for (std::size_t r = 0; r < c_.regions.size(); ++r) {
            map(c_.regions[r].coefficients,
                "region " + std::to_string(r) + " '" + c_.regions[r].name + "' coefficients");
        }
        if (c_.composed) {
            map(*c_.composed, "composed coefficients");
        }
        std::set<std::string> names;
        for (std::size_t p = 0; p < c_.presets.size(); ++p) {
            preset(c_.presets[p], "preset " + std::to_string(p) + " '" + c_.presets[p].name + "'",
                   names);
        }
    }

private:
    [[noreturn]] void fail(const std::string& problem) const {
        throw common::InputError(path_, problem);
    }

    void ruleFromProto(const std::string& problem) const {
        if (!problem.empty()) {
            fail(problem);
        }
    }

    void finite(const std::vector<float>& values, const std::string& what, float limit) const {
        for (std::size_t i = 0; i < values.size(); ++i) {
            if (!(std::fabs(values[i]) <= limit)) {
                fail(
                    what + ": value " + std::to_string(i) + " (" + std::to_string(values[i]) +
                    (std::isfinite(values[i]) ? ") does not fit a half float" : ") is not finite"));
            }
        }
    }

    void count(std::size_t actual, std::size_t expected, const std::string& what) const {
        if (actual != expected) {
            fail(what + ": " + std::to_string(actual) + " values, expected " +
                 std::to_string(expected));
        }
    }

    void radiometry(const BundleRadiometry& r) const {
        const std::size_t values =
            3 * static_cast<std::size_t>(c_.projector.width) * c_.projector.height;
        count(r.irradiance.size(), values, "radiometry irradiance");
        count(r.floor.size(), values, "radiometry floor");
        for (const std::vector<float>* map : {&r.irradiance, &r.floor}) {
            for (const float v : *map) {
                if (!std::isfinite(v) || v < 0 || v > 65504.0f) {
                    fail("radiometry: a map value outside [0, 65504] (half floats)");
                }
            }
        }
        switch (proto::checkMixing(r.mixing)) {
            case proto::MixingRule::kHolds:
                break;
            case proto::MixingRule::kNotFiniteOrNegative:
                fail("radiometry: mixing: expected finite values ≥ 0");
            case proto::MixingRule::kDiagonalNotOne:
                fail("radiometry: mixing: its diagonal must be 1");
            case proto::MixingRule::kSingular:
                fail("radiometry: mixing: it must be invertible (the device inverts it)");
        }
    }

    void blend(const BundleBlend& b) const {
        if (!proto::blendIndexFits(b.index, b.projectors)) {
            fail("blend: projector " + std::to_string(b.index) + " of " +
                 std::to_string(b.projectors));
        }
        count(b.share.size(), static_cast<std::size_t>(c_.projector.width) * c_.projector.height,
              "blend share");
        for (const float v : b.share) {
            ruleFromProto(proto::checkBlendShare(v));
        }
    }

    void mesh() const {
        const BundleMesh& m = c_.mesh;
        if (m.positions.empty() || m.positions.size() % 3 != 0) {
            fail("mesh positions: " + std::to_string(m.positions.size()) +
                 " values, not a positive multiple of 3");
        }
        const std::size_t vertices = m.positions.size() / 3;
        if (vertices > UINT32_MAX) {
            fail("mesh: more than 2^32 vertices");
        }
        count(m.normals.size(), 3 * vertices, "mesh normals");
        count(m.uvs.size(), 2 * vertices, "mesh uvs");
        if (m.indices.empty() || m.indices.size() % 3 != 0) {
            fail("mesh indices: " + std::to_string(m.indices.size()) +
                 " values, not a positive multiple of 3");
        }
        const float inf = std::numeric_limits<float>::max();
        finite(m.positions, "mesh positions", inf);
        finite(m.normals, "mesh normals", inf);
        finite(m.uvs, "mesh uvs", inf);
        ruleFromProto(proto::checkMeshIndices(m.indices, vertices));
    }

    void map(const CoefficientMapData& map, const std::string& what) const {
        detailNormals(map, what);
        const std::size_t c = static_cast<std::size_t>(c_.model.coefficientsPerTexel());
        if (map.encoding == proto::CoefficientEncoding::kFull) {
            count(map.coefficients.size(), texels(c_) * c, what);
            finite(map.coefficients, what, kHalfMax);
            return;
        }
        ruleFromProto(proto::checkRank(what, map.rank, static_cast<std::int64_t>(c)));
        const auto rank = static_cast<std::size_t>(map.rank);
        const float inf = std::numeric_limits<float>::max();
        count(map.mean.size(), c, what + " mean");
        finite(map.mean, what + " mean", inf);
        count(map.basis.size(), rank * c, what + " basis");
        finite(map.basis, what + " basis", inf);
        count(map.weights.size(), texels(c_) * rank, what + " weights");
        finite(map.weights, what + " weights", kHalfMax);
    }

    void detailNormals(const CoefficientMapData& map, const std::string& what) const {
        if (map.detailNormals.empty()) {
            return;
        }
        count(map.detailNormals.size(), 2 * texels(c_), what + " detail normals");
        for (std::size_t t = 0; t < texels(c_); ++t) {
            const double x = map.detailNormals[2 * t], y = map.detailNormals[2 * t + 1];
            if (!(x * x + y * y <= 1.0 + 1e-6)) {
                fail(what + " detail normals: texel (" +
                     std::to_string(t % static_cast<std::size_t>(c_.textureWidth)) + ", " +
                     std::to_string(t / static_cast<std::size_t>(c_.textureWidth)) + ") is (" +
                     std::to_string(x) + ", " + std::to_string(y) +
                     "), not the x and y of a unit normal");
            }
        }
    }

    void preset(const WeightPreset& preset, const std::string& what,
                std::set<std::string>& names) const {
        if (preset.name.empty()) {
            fail(what + ": a preset needs a name");
        }
        if (!names.insert(preset.name).second) {
            fail(what + ": another preset has the same name");
        }
        const std::size_t n = texels(c_);
        const std::size_t regions = c_.regions.size();
        count(preset.alpha.size(), regions * n, what + " alpha");
        for (std::size_t t = 0; t < n; ++t) {
            double sum = 0;
            for (std::size_t k = 0; k < regions; ++k) {
                const float a = preset.alpha[k * n + t];
                if (!(std::isfinite(a) && a >= 0)) {
                    fail(what + " alpha: region " + std::to_string(k) + " at texel (" +
                         std::to_string(t % static_cast<std::size_t>(c_.textureWidth)) + ", " +
                         std::to_string(t / static_cast<std::size_t>(c_.textureWidth)) + ") is " +
                         std::to_string(a) + ", not a finite value ≥ 0");
                }
                sum += static_cast<double>(a);
            }
            if (std::fabs(sum - 1.0) > kAlphaSumTolerance) {
                fail(what + " alpha: sums to " + std::to_string(sum) + " at texel (" +
                     std::to_string(t % static_cast<std::size_t>(c_.textureWidth)) + ", " +
                     std::to_string(t / static_cast<std::size_t>(c_.textureWidth)) + "), not 1");
            }
        }
    }

    const std::filesystem::path& path_;
    const BundleContents& c_;
};

// ---- writing -----------------------------------------------------------------------------

// The output file: counts and checksums what goes in after the header.
class BundleOutput {
public:
    BundleOutput(const std::filesystem::path& temporary, const std::filesystem::path& name)
        : name_(name), file_(std::fopen(temporary.c_str(), "wb")) {
        if (file_ == nullptr) {
            fail("cannot create");
        }
        std::setvbuf(file_, nullptr, _IOFBF, std::size_t{1} << 20);
    }
    ~BundleOutput() {
        if (file_ != nullptr) {
            std::fclose(file_);
        }
    }
    BundleOutput(const BundleOutput&) = delete;
    BundleOutput& operator=(const BundleOutput&) = delete;

    void write(const void* data, std::size_t size, bool checksummed = true) {
        if (size > 0 && std::fwrite(data, 1, size, file_) != size) {
            fail("cannot write");
        }
        if (checksummed) {
            checksum_ =
                proto::bundleChecksum({static_cast<const std::byte*>(data), size}, checksum_);
        }
        offset_ += size;
    }
    template <typename T>
    void write(const std::vector<T>& values) {
        write(values.data(), values.size() * sizeof(T));
    }
    void padTo(std::uint64_t offset) {
        static constexpr std::byte kZeros[proto::kBundlePayloadAlignment] = {};
        if (offset < offset_ || offset - offset_ > sizeof kZeros) {
            throw std::logic_error("bundle writer: bad padding");
        }
        write(kZeros, static_cast<std::size_t>(offset - offset_));
    }
    std::uint64_t offset() const { return offset_; }
    std::uint32_t checksum() const { return checksum_; }

    // Writes the header over the placeholder and makes the file durable before the rename.
    void finish(const proto::BundleHeaderBytes& header) {
        if (std::fseek(file_, 0, SEEK_SET) != 0 ||
            std::fwrite(header.data(), 1, header.size(), file_) != header.size() ||
            std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
            fail("cannot write");
        }
        const int closed = std::fclose(file_);
        file_ = nullptr;
        if (closed != 0) {
            fail("cannot write");
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw common::InputError(name_, what + ": " + std::strerror(errno));
    }

    std::filesystem::path name_;
    std::FILE* file_;
    std::uint64_t offset_ = 0;
    std::uint32_t checksum_ = 0;
};

// The payloads in file order: where each goes (proto's bundle layout, shared with the test
// bundles) and how to stream it.
struct PayloadPlan {
    proto::BundleLayout layout;
    std::vector<std::function<void(BundleOutput&)>> writers;
};

std::size_t addPayload(PayloadPlan& payloads, fb::ElementType type,
                       std::vector<std::uint32_t> shape, std::function<void(BundleOutput&)> write) {
    payloads.writers.push_back(std::move(write));
    return payloads.layout.add(type, std::move(shape));
}

// `values` per texel (C coefficients or R weights), packed four to an RGBA16F layer:
// layer-major, rows top to bottom, zero padding past the last value.
void writeHalfLayers(BundleOutput& out, const std::vector<float>& values, std::size_t perTexel,
                     std::uint32_t layers, std::uint32_t width, std::uint32_t height) {
    std::vector<std::uint16_t> row(static_cast<std::size_t>(width) * 4);
    for (std::uint32_t layer = 0; layer < layers; ++layer) {
        for (std::uint32_t y = 0; y < height; ++y) {
            const float* texel = values.data() + static_cast<std::size_t>(y) * width * perTexel;
            for (std::uint32_t x = 0; x < width; ++x, texel += perTexel) {
                for (std::uint32_t j = 0; j < 4; ++j) {
                    const std::size_t i = 4 * layer + j;
                    row[4 * x + j] = proto::floatToHalf(i < perTexel ? texel[i] : 0.0f);
                }
            }
            out.write(row);
        }
    }
}

std::size_t addHalfLayers(PayloadPlan& payloads, const std::vector<float>& values, int perTexel,
                          int width, int height) {
    const auto layers = static_cast<std::uint32_t>((perTexel + 3) / 4);
    const auto w = static_cast<std::uint32_t>(width);
    const auto h = static_cast<std::uint32_t>(height);
    const auto stride = static_cast<std::size_t>(perTexel);
    return addPayload(payloads, fb::ElementType::Float16, {layers, h, w, 4},
                      [&values, stride, layers, w, h](BundleOutput& out) {
                          writeHalfLayers(out, values, stride, layers, w, h);
                      });
}

// α normalized to sum 1 exactly at each texel ([region][texel] in and out).
std::vector<float> normalizedAlpha(const std::vector<float>& alpha, std::size_t regions,
                                   std::size_t texelCount) {
    std::vector<float> normalized(alpha.size());
    for (std::size_t t = 0; t < texelCount; ++t) {
        double sum = 0;
        for (std::size_t k = 0; k < regions; ++k) {
            sum += static_cast<double>(alpha[k * texelCount + t]);
        }
        for (std::size_t k = 0; k < regions; ++k) {
            normalized[k * texelCount + t] =
                static_cast<float>(static_cast<double>(alpha[k * texelCount + t]) / sum);
        }
    }
    return normalized;
}

// 8-bit weights that add up to exactly 255 at each texel (largest remainder), so that the
// blend of the regions never gains or loses light.
std::vector<std::uint8_t> quantizeAlpha(const std::vector<float>& alpha, std::size_t regions,
                                        std::size_t texelCount) {
    const std::vector<float> normalized = normalizedAlpha(alpha, regions, texelCount);
    std::vector<std::uint8_t> quantized(alpha.size());
    std::vector<double> remainder(regions);
    std::vector<std::size_t> order(regions);
    for (std::size_t t = 0; t < texelCount; ++t) {
        int left = 255;
        for (std::size_t k = 0; k < regions; ++k) {
            const double scaled = 255.0 * static_cast<double>(normalized[k * texelCount + t]);
            const double whole = std::min(std::floor(scaled), 255.0);
            quantized[k * texelCount + t] = static_cast<std::uint8_t>(whole);
            remainder[k] = scaled - whole;
            left -= static_cast<int>(whole);
        }
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return remainder[a] > remainder[b]; });
        for (std::size_t i = 0; i < order.size() && left > 0; ++i, --left) {
            ++quantized[order[i] * texelCount + t];
        }
    }
    return quantized;
}

std::vector<std::uint16_t> halfAlpha(const std::vector<float>& alpha, std::size_t regions,
                                     std::size_t texelCount) {
    const std::vector<float> normalized = normalizedAlpha(alpha, regions, texelCount);
    std::vector<std::uint16_t> halves(normalized.size());
    std::transform(normalized.begin(), normalized.end(), halves.begin(), proto::floatToHalf);
    return halves;
}

std::size_t addAlpha(PayloadPlan& payloads, const WeightPreset& preset, std::size_t regions,
                     int width, int height) {
    const std::vector<std::uint32_t> shape{static_cast<std::uint32_t>(regions),
                                           static_cast<std::uint32_t>(height),
                                           static_cast<std::uint32_t>(width)};
    const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (preset.encoding == proto::AlphaEncoding::kUnorm8) {
        return addPayload(payloads, fb::ElementType::UInt8, shape,
                          [&preset, regions, n](BundleOutput& out) {
                              out.write(quantizeAlpha(preset.alpha, regions, n));
                          });
    }
    return addPayload(payloads, fb::ElementType::Float16, shape,
                      [&preset, regions, n](BundleOutput& out) {
                          out.write(halfAlpha(preset.alpha, regions, n));
                      });
}

// Which payload holds what (indices into the payload list).
struct MapPayloads {
    std::size_t layers = 0;  // coefficients (full) or weights (low rank)
    std::optional<std::size_t> detailNormals;
};
struct PayloadIndex {
    std::size_t positions = 0, normals = 0, uvs = 0, indices = 0;
    std::vector<MapPayloads> regions;
    std::optional<MapPayloads> composed;
    std::vector<std::size_t> presets;
    std::optional<std::array<std::size_t, 2>> radiometry;  // irradiance, floor
    std::optional<std::size_t> blendShare;
};

PayloadIndex planPayloads(const BundleContents& c, PayloadPlan& payloads) {
    PayloadIndex index;
    const auto vertices = static_cast<std::uint32_t>(c.mesh.positions.size() / 3);
    const auto triangles = static_cast<std::uint32_t>(c.mesh.indices.size() / 3);
    const auto raw = [](const auto& values) {
        return [&values](BundleOutput& out) { out.write(values); };
    };
    index.positions =
        addPayload(payloads, fb::ElementType::Float32, {vertices, 3}, raw(c.mesh.positions));
    index.normals =
        addPayload(payloads, fb::ElementType::Float32, {vertices, 3}, raw(c.mesh.normals));
    index.uvs = addPayload(payloads, fb::ElementType::Float32, {vertices, 2}, raw(c.mesh.uvs));
    index.indices =
        addPayload(payloads, fb::ElementType::UInt32, {triangles, 3}, raw(c.mesh.indices));
    const auto planMap = [&](const CoefficientMapData& map) {
        const bool full = map.encoding == proto::CoefficientEncoding::kFull;
        MapPayloads planned{addHalfLayers(payloads, full ? map.coefficients : map.weights,
                                          full ? c.model.coefficientsPerTexel() : map.rank,
                                          c.textureWidth, c.textureHeight),
                            std::nullopt};
        if (!map.detailNormals.empty()) {
            planned.detailNormals =
                addPayload(payloads, fb::ElementType::Float16,
                           {static_cast<std::uint32_t>(c.textureHeight),
                            static_cast<std::uint32_t>(c.textureWidth), 2},
                           [&map](BundleOutput& out) {
                               std::vector<std::uint16_t> halves(map.detailNormals.size());
                               std::transform(map.detailNormals.begin(), map.detailNormals.end(),
                                              halves.begin(), proto::floatToHalf);
                               out.write(halves);
                           });
        }
        return planned;
    };
    for (const BundleRegion& region : c.regions) {
        index.regions.push_back(planMap(region.coefficients));
    }
    if (c.composed) {
        index.composed = planMap(*c.composed);
    }
    for (const WeightPreset& preset : c.presets) {
        index.presets.push_back(
            addAlpha(payloads, preset, c.regions.size(), c.textureWidth, c.textureHeight));
    }
    if (c.radiometry) {
        // r, g, b and a zero per projector pixel: an RGBA16F texture the device samples as is.
        const auto rgba = [](const std::vector<float>& rgb) {
            return [&rgb](BundleOutput& out) {
                std::vector<std::uint16_t> halves(rgb.size() / 3 * 4, 0);
                for (std::size_t p = 0; 3 * p < rgb.size(); ++p) {
                    for (std::size_t k = 0; k < 3; ++k) {
                        halves[4 * p + k] = proto::floatToHalf(rgb[3 * p + k]);
                    }
                }
                out.write(halves);
            };
        };
        const std::vector<std::uint32_t> shape{c.projector.height, c.projector.width, 4};
        index.radiometry = std::array<std::size_t, 2>{
            addPayload(payloads, fb::ElementType::Float16, shape, rgba(c.radiometry->irradiance)),
            addPayload(payloads, fb::ElementType::Float16, shape, rgba(c.radiometry->floor))};
    }
    if (c.blend) {
        index.blendShare = addPayload(
            payloads, fb::ElementType::Float16, {c.projector.height, c.projector.width},
            [&share = c.blend->share](BundleOutput& out) {
                std::vector<std::uint16_t> halves(share.size());
                std::transform(share.begin(), share.end(), halves.begin(), proto::floatToHalf);
                out.write(halves);
            });
    }
    return index;
}

// ---- metadata ----------------------------------------------------------------------------

class MetadataBuilder {
public:
    MetadataBuilder(const BundleContents& c, const std::vector<proto::PayloadPlacement>& payloads,
                    const PayloadIndex& index)
        : c_(c), payloads_(payloads), index_(index) {}

    std::vector<std::uint8_t> build() {
        flatbuffers::FlatBufferBuilder b(4096);
        const auto mesh = fb::CreateMesh(b, ref(b, index_.positions), ref(b, index_.normals),
                                         ref(b, index_.uvs), ref(b, index_.indices));
        const auto projector = buildPinhole(b, c_.projector);
        // No camera: the field stays absent, as in a 1.2 bundle.
        const auto camera =
            c_.camera ? buildPinhole(b, *c_.camera) : flatbuffers::Offset<fb::Projector>();
        const auto settings = buildSettings(b);
        // No basis: the field stays absent, as in a 1.0 bundle (the device renders exactly).
        const std::vector<float>* thetaBasis =
            c_.model.thetaBasis.empty() ? nullptr : &c_.model.thetaBasis;
        const auto model =
            fb::CreateModelDirect(b, static_cast<std::uint16_t>(c_.model.harmonics),
                                  c_.model.lambda, proto::kBundleCoefficientLayout, thetaBasis);
        std::vector<flatbuffers::Offset<fb::Region>> regions;
        for (std::size_t r = 0; r < c_.regions.size(); ++r) {
            const auto map = buildMap(b, c_.regions[r].coefficients, index_.regions[r]);
            regions.push_back(fb::CreateRegionDirect(b, c_.regions[r].name.c_str(), map));
        }
        flatbuffers::Offset<fb::CoefficientMap> composed;
        if (c_.composed) {
            composed = buildMap(b, *c_.composed, *index_.composed);
        }
        std::vector<flatbuffers::Offset<fb::WeightPreset>> presets;
        for (std::size_t i = 0; i < c_.presets.size(); ++i) {
            presets.push_back(fb::CreateWeightPresetDirect(b, c_.presets[i].name.c_str(),
                                                           ref(b, index_.presets[i])));
        }
        const auto textures =
            fb::CreateTexturesDirect(b, static_cast<std::uint32_t>(c_.textureWidth),
                                     static_cast<std::uint32_t>(c_.textureHeight), &regions,
                                     composed, &presets, c_.textureWrapsU);
        flatbuffers::Offset<fb::Radiometry> radiometry;
        if (c_.radiometry) {
            const fb::Mat3d mixing(flatbuffers::make_span(c_.radiometry->mixing));
            radiometry = fb::CreateRadiometry(b, &mixing, ref(b, (*index_.radiometry)[0]),
                                              ref(b, (*index_.radiometry)[1]));
        }
        flatbuffers::Offset<fb::Blend> blend;
        if (c_.blend) {
            blend = fb::CreateBlend(b, static_cast<std::uint16_t>(c_.blend->projectors),
                                    static_cast<std::uint16_t>(c_.blend->index),
                                    ref(b, *index_.blendShare));
        }
        fb::FinishBundleBuffer(b, fb::CreateBundle(b, mesh, projector, settings, model, textures,
                                                   camera, radiometry, blend));
        return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
    }

private:
    // The projector's table, for the projector and for the camera.
    static flatbuffers::Offset<fb::Projector> buildPinhole(flatbuffers::FlatBufferBuilder& b,
                                                           const proto::ProjectorCalibration& p) {
        const fb::Mat3d intrinsics(flatbuffers::make_span(p.intrinsics));
        const fb::Mat3d rotation(flatbuffers::make_span(p.rotation));
        const fb::Distortion distortion(p.distortion[0], p.distortion[1], p.distortion[2],
                                        p.distortion[3], p.distortion[4]);
        const fb::Vec3d translation(p.translation[0], p.translation[1], p.translation[2]);
        return fb::CreateProjector(b, p.width, p.height, &intrinsics, &distortion, &rotation,
                                   &translation);
    }

    flatbuffers::Offset<fb::Payload> ref(flatbuffers::FlatBufferBuilder& b, std::size_t i) {
        return proto::payloadReference(b, payloads_[i]);
    }

    flatbuffers::Offset<fb::RenderSettings> buildSettings(flatbuffers::FlatBufferBuilder& b) {
        const proto::RenderSettings& s = c_.settings;
        flatbuffers::Offset<void> response;
        fb::ProjectorResponse kind;
        if (s.response.kind == proto::ResponseKind::kGamma) {
            const fb::Rgb gamma(s.response.gamma[0], s.response.gamma[1], s.response.gamma[2]);
            response = fb::CreateGammaResponse(b, &gamma).Union();
            kind = fb::ProjectorResponse::GammaResponse;
        } else {
            response = fb::CreateCurveResponseDirect(b, &s.response.curve[0], &s.response.curve[1],
                                                     &s.response.curve[2])
                           .Union();
            kind = fb::ProjectorResponse::CurveResponse;
        }
        const fb::Vec3f viewer(s.viewerPosition[0], s.viewerPosition[1], s.viewerPosition[2]);
        const fb::Rgb albedo(s.screenAlbedo[0], s.screenAlbedo[1], s.screenAlbedo[2]);
        const fb::Rgb ambient(s.ambientIrradiance[0], s.ambientIrradiance[1],
                              s.ambientIrradiance[2]);
        std::vector<fb::Vec3f> zone;
        for (const auto& eye : s.viewingZone) {
            zone.emplace_back(eye[0], eye[1], eye[2]);
        }
        return fb::CreateRenderSettings(b, &viewer, &albedo, &ambient, kind, response,
                                        s.peakIrradiance, s.gain,
                                        zone.empty() ? 0 : b.CreateVectorOfStructs(zone));
    }

    flatbuffers::Offset<fb::CoefficientMap> buildMap(flatbuffers::FlatBufferBuilder& b,
                                                     const CoefficientMapData& map,
                                                     const MapPayloads& payloads) {
        // Absent without a relief: such a map reads exactly as in a 1.1 bundle.
        const flatbuffers::Offset<fb::Payload> detail = payloads.detailNormals
                                                            ? ref(b, *payloads.detailNormals)
                                                            : flatbuffers::Offset<fb::Payload>();
        if (map.encoding == proto::CoefficientEncoding::kFull) {
            const auto full = fb::CreateFullCoefficients(b, ref(b, payloads.layers));
            return fb::CreateCoefficientMap(b, fb::CoefficientEncoding::FullCoefficients,
                                            full.Union(), detail);
        }
        const auto lowRank =
            fb::CreateLowRankCoefficientsDirect(b, static_cast<std::uint16_t>(map.rank), &map.mean,
                                                &map.basis, ref(b, payloads.layers));
        return fb::CreateCoefficientMap(b, fb::CoefficientEncoding::LowRankCoefficients,
                                        lowRank.Union(), detail);
    }

    const BundleContents& c_;
    const std::vector<proto::PayloadPlacement>& payloads_;
    const PayloadIndex& index_;
};

}  // namespace

BundleWriteResult writeBundle(const std::filesystem::path& path, const BundleContents& contents) {
    ContentsCheck(path, contents).run();

    PayloadPlan payloads;
    const PayloadIndex index = planPayloads(contents, payloads);
    const std::vector<std::uint8_t> metadata =
        payloads.layout.settle([&](const std::vector<proto::PayloadPlacement>& placed) {
            return MetadataBuilder(contents, placed, index).build();
        });

    proto::AtomicFile output(path);
    proto::BundleHeader header = payloads.layout.header();
    {
        BundleOutput out(output.temporaryPath(), path);
        const proto::BundleHeaderBytes placeholder{};
        out.write(placeholder.data(), placeholder.size(), /*checksummed=*/false);
        out.write(metadata);
        const std::vector<proto::PayloadPlacement>& placed = payloads.layout.payloads();
        for (std::size_t i = 0; i < placed.size(); ++i) {
            out.padTo(placed[i].offset);
            payloads.writers[i](out);
            if (out.offset() != placed[i].offset + placed[i].size) {
                throw std::logic_error("bundle writer: payload size differs from its plan");
            }
        }
        if (out.offset() != header.fileSize) {
            throw std::logic_error("bundle writer: file size differs from its layout");
        }
        header.checksum = out.checksum();
        out.finish(proto::encodeBundleHeader(header));
    }
    // What the device will do with it, before it takes the final name.
    try {
        proto::BundleFile::open(output.temporaryPath());
    } catch (const proto::BundleError& error) {
        throw std::logic_error("bundle writer: the reader refuses the written bundle: " +
                               error.problem());
    }
    output.commit();
    return {header.fileSize, header.checksum};
}

}  // namespace vpe::bake
