// SPDX-License-Identifier: MIT
// BundleView::parse: every check between a bundle's bytes and the spans the renderer reads —
// header, checksum, FlatBuffers verification, then each field's meaning and each payload's
// type, shape, size, alignment and bounds. Nothing is read that has not been checked.
#include "vpe/proto/bundle.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <utility>

#include "vpe/proto/bundle_generated.h"
#include "vpe/proto/half_float.h"

#include "printable_text.h"

namespace vpe::proto {

namespace {

// Enough for any real bundle (a few tables per region and preset), and a bound on the
// verifier's work for hostile metadata.
constexpr flatbuffers::uoffset_t kMaxMetadataTables = 100000;

std::string hex32(std::uint32_t value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", static_cast<unsigned>(value));
    return text;
}

const char* elementTypeName(fb::ElementType type) {
    switch (type) {
        case fb::ElementType::Float32:
            return "float32";
        case fb::ElementType::Float16:
            return "float16";
        case fb::ElementType::UInt32:
            return "uint32";
        case fb::ElementType::UInt8:
            return "uint8";
    }
    return nullptr;
}

std::string typeName(fb::ElementType type) {
    const char* name = elementTypeName(type);
    return name != nullptr ? name : "unknown type " + std::to_string(static_cast<int>(type));
}

std::uint64_t elementSize(fb::ElementType type) {
    switch (type) {
        case fb::ElementType::Float32:
        case fb::ElementType::UInt32:
            return 4;
        case fb::ElementType::Float16:
            return 2;
        case fb::ElementType::UInt8:
            return 1;
    }
    return 0;
}

std::string shapeText(const std::vector<std::uint64_t>& shape) {
    std::string text = "[";
    for (std::size_t i = 0; i < shape.size(); ++i) {
        text += (i > 0 ? ", " : "") + std::to_string(shape[i]);
    }
    return text + "]";
}

std::vector<std::uint64_t> shapeOf(const fb::Payload& payload) {
    std::vector<std::uint64_t> shape;
    if (payload.shape() != nullptr) {
        for (std::uint32_t dim : *payload.shape()) {
            shape.push_back(dim);
        }
    }
    return shape;
}

// Names and the layout come from the file: quoted and escaped, to keep messages one line.
std::string quoted(std::string_view name) {
    return "'" + printableText(name) + "'";
}

std::string_view stringOf(const flatbuffers::String* s) {
    return s != nullptr ? std::string_view(s->c_str(), s->size()) : std::string_view();
}

std::uint32_t layersFor(std::uint32_t values) {
    return (values + 3) / 4;
}

}  // namespace

// Decodes one bundle; a class so that every check can name the file without passing it.
class BundleDecoder {
public:
    BundleDecoder(std::span<const std::byte> bytes, const std::string& name)
        : bytes_(bytes), name_(name) {}

    BundleView decode(const BundleOpenOptions& options) {
        BundleView view;
        view.bytes_ = bytes_;
        view.name_ = name_;
        view.header_ = decodeBundleHeader(bytes_, name_);
        if (options.verifyChecksum) {
            view.verifyChecksum();
        }
        const fb::Bundle& root = verifiedMetadata(view.header_);
        decodeModel(view, root);
        decodeProjector(view, root);
        decodeCamera(view, root);
        decodeRadiometry(view, root);
        decodeBlend(view, root);
        decodeSettings(view, root);
        decodeMesh(view, root);
        decodeTextures(view, root);
        return view;
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw BundleError(name_, problem); }

    const fb::Bundle& verifiedMetadata(const BundleHeader& header) {
        const std::uint64_t offset = header.metadataOffset;
        const std::uint64_t size = header.metadataSize;
        if (offset < kBundleHeaderSize) {
            fail("metadata at offset " + std::to_string(offset) + " overlaps the header");
        }
        // FlatBuffers aligns scalars to their size (doubles and ulongs: 8) relative to the
        // buffer's start; the file's start is 64-byte aligned, so the metadata's must be 8.
        if (offset % 8 != 0) {
            fail("metadata offset " + std::to_string(offset) + " is not a multiple of 8");
        }
        if (size == 0 || offset > header.fileSize || size > header.fileSize - offset) {
            fail("metadata of " + std::to_string(size) + " bytes at offset " +
                 std::to_string(offset) + " does not fit in the file (" +
                 std::to_string(header.fileSize) + " bytes)");
        }
        if (size >= FLATBUFFERS_MAX_BUFFER_SIZE) {
            fail("metadata of " + std::to_string(size) +
                 " bytes is larger than FlatBuffers allows");
        }
        const auto* data = reinterpret_cast<const std::uint8_t*>(bytes_.data() + offset);
        flatbuffers::Verifier::Options verifierOptions;
        verifierOptions.max_tables = kMaxMetadataTables;
        flatbuffers::Verifier verifier(data, static_cast<std::size_t>(size), verifierOptions);
        if (!fb::VerifyBundleBuffer(verifier)) {
            fail("metadata is not a valid bundle FlatBuffer (identifier 'VPEM')");
        }
        payloadBegin_ = offset + size;
        return *fb::GetBundle(data);
    }

    void decodeModel(BundleView& view, const fb::Bundle& root) {
        const fb::Model* model = root.model();
        if (model == nullptr) {
            fail("metadata has no model");
        }
        const std::string_view layout = stringOf(model->layout());
        if (layout != kBundleCoefficientLayout) {
            fail("model: coefficient layout " + quoted(layout) + ", this reader knows " +
                 quoted(kBundleCoefficientLayout));
        }
        view.model_.harmonics = model->harmonics();
        view.model_.lambda = model->lambda();
        // 1.1's θs basis; a 1.0 bundle has none (rendered exactly). Copied: at most
        // (2M + 1)² floats, and checked whole (checkModel) before anything renders with it.
        if (const flatbuffers::Vector<float>* basis = model->theta_basis(); basis != nullptr) {
            view.model_.thetaBasis.assign(basis->begin(), basis->end());
        }
        if (const std::string problem = checkModel(view.model_); !problem.empty()) {
            fail(problem);
        }
    }

    void decodeProjector(BundleView& view, const fb::Bundle& root) {
        view.projector_ = decodePinhole(root.projector(), "projector");
        if (const std::string problem = checkProjector(view.projector_); !problem.empty()) {
            fail(problem);
        }
    }

    // 1.3's camera: absent in older bundles and optional in newer ones; when present, held to
    // the projector's rules.
    void decodeCamera(BundleView& view, const fb::Bundle& root) {
        if (root.camera() == nullptr) {
            return;
        }
        const ProjectorCalibration camera = decodePinhole(root.camera(), "camera");
        if (const std::string problem = checkBundleCamera(camera); !problem.empty()) {
            fail(problem);
        }
        view.camera_ = camera;
    }

    // 1.4's measured light: absent in older bundles and optional in newer ones. Its maps have
    // the projector's size; every value finite, F and D not negative, X's diagonal 1 and X
    // invertible (the device inverts it).
    void decodeRadiometry(BundleView& view, const fb::Bundle& root) {
        const fb::Radiometry* table = root.radiometry();
        if (table == nullptr) {
            return;
        }
        RadiometryView r;
        if (table->mixing() == nullptr) {
            fail("radiometry: mixing missing");
        }
        for (flatbuffers::uoffset_t i = 0; i < 9; ++i) {
            r.mixing[i] = table->mixing()->m()->Get(i);
        }
        switch (checkMixing(r.mixing)) {
            case MixingRule::kHolds:
                break;
            case MixingRule::kNotFiniteOrNegative:
                fail("radiometry: mixing: expected finite values ≥ 0");
            case MixingRule::kDiagonalNotOne:
            case MixingRule::kSingular:
                fail("radiometry: mixing: its diagonal must be 1 and it must be invertible");
        }
        const std::vector<std::uint64_t> shape{view.projector_.height, view.projector_.width, 4};
        if (table->irradiance() == nullptr || table->floor() == nullptr) {
            fail("radiometry: irradiance or floor missing");
        }
        r.irradiance = typed<std::uint16_t>(table->irradiance(), "radiometry irradiance",
                                            {fb::ElementType::Float16}, shape);
        r.floor = typed<std::uint16_t>(table->floor(), "radiometry floor",
                                       {fb::ElementType::Float16}, shape);
        for (const auto& [values, what] :
             {std::pair{r.irradiance, "irradiance"}, std::pair{r.floor, "floor"}}) {
            for (const std::uint16_t half : values) {
                const float v = halfToFloat(half);
                if (!std::isfinite(v) || v < 0) {
                    fail(std::string("radiometry ") + what +
                         ": a value that is negative or not "
                         "finite");
                }
            }
        }
        view.radiometry_ = r;
    }

    // 1.5's blend: absent in older bundles and in a single projector's. Its share map has the
    // projector's size, every value in [0, 1].
    void decodeBlend(BundleView& view, const fb::Bundle& root) {
        const fb::Blend* table = root.blend();
        if (table == nullptr) {
            return;
        }
        BlendView blend;
        blend.projectors = table->projectors();
        blend.index = table->index();
        if (!blendIndexFits(blend.index, blend.projectors)) {
            fail("blend: projector " + std::to_string(blend.index) + " of " +
                 std::to_string(blend.projectors) + " (expected index < projectors, ≥ 1)");
        }
        if (table->share() == nullptr) {
            fail("blend: share missing");
        }
        blend.share =
            typed<std::uint16_t>(table->share(), "blend share", {fb::ElementType::Float16},
                                 {view.projector_.height, view.projector_.width});
        for (const std::uint16_t half : blend.share) {
            if (const std::string problem = checkBlendShare(halfToFloat(half)); !problem.empty()) {
                fail(problem);
            }
        }
        view.blend_ = blend;
    }

    // A Projector table (the projector's or the camera's) into its struct, unchecked.
    ProjectorCalibration decodePinhole(const fb::Projector* table, const std::string& what) {
        if (table == nullptr) {
            fail("metadata has no " + what);
        }
        const fb::Mat3d* intrinsics = table->intrinsics();
        const fb::Mat3d* rotation = table->rotation();
        const fb::Distortion* distortion = table->distortion();
        const fb::Vec3d* translation = table->translation();
        if (intrinsics == nullptr || distortion == nullptr || rotation == nullptr ||
            translation == nullptr) {
            fail(what + ": intrinsics, distortion, rotation or translation missing");
        }
        ProjectorCalibration p;
        p.width = table->width();
        p.height = table->height();
        for (flatbuffers::uoffset_t i = 0; i < 9; ++i) {
            p.intrinsics[i] = intrinsics->m()->Get(i);
            p.rotation[i] = rotation->m()->Get(i);
        }
        p.distortion = {distortion->k1(), distortion->k2(), distortion->p1(), distortion->p2(),
                        distortion->k3()};
        p.translation = {translation->x(), translation->y(), translation->z()};
        return p;
    }

    void decodeSettings(BundleView& view, const fb::Bundle& root) {
        const fb::RenderSettings* settings = root.settings();
        if (settings == nullptr) {
            fail("metadata has no render settings");
        }
        const fb::Vec3f* viewer = settings->viewer_position();
        const fb::Rgb* albedo = settings->screen_albedo();
        if (viewer == nullptr || albedo == nullptr) {
            fail("settings: viewer position or screen albedo missing");
        }
        RenderSettings& s = view.settings_;
        s.viewerPosition = {viewer->x(), viewer->y(), viewer->z()};
        s.screenAlbedo = {albedo->r(), albedo->g(), albedo->b()};
        s.ambientIrradiance = {0.0f, 0.0f, 0.0f};
        if (const fb::Rgb* ambient = settings->ambient_irradiance(); ambient != nullptr) {
            s.ambientIrradiance = {ambient->r(), ambient->g(), ambient->b()};
        }
        s.peakIrradiance = settings->peak_irradiance();
        s.gain = settings->gain();
        if (const auto* zone = settings->viewing_zone(); zone != nullptr) {
            for (const fb::Vec3f* eye : *zone) {
                s.viewingZone.push_back({eye->x(), eye->y(), eye->z()});
            }
        }
        if (const fb::GammaResponse* gamma = settings->response_as_GammaResponse()) {
            const fb::Rgb* exponents = gamma->gamma();
            if (exponents == nullptr) {
                fail("settings: response gamma missing");
            }
            s.response.kind = ResponseKind::kGamma;
            s.response.gamma = {exponents->r(), exponents->g(), exponents->b()};
        } else if (const fb::CurveResponse* curve = settings->response_as_CurveResponse()) {
            s.response.kind = ResponseKind::kCurve;
            const flatbuffers::Vector<float>* channels[3] = {curve->red(), curve->green(),
                                                             curve->blue()};
            for (int c = 0; c < 3; ++c) {
                if (channels[c] != nullptr) {
                    s.response.curve[c].assign(channels[c]->begin(), channels[c]->end());
                }
            }
        } else {
            fail("settings: projector response missing or of an unknown kind");
        }
        if (const std::string problem = checkSettings(s); !problem.empty()) {
            fail(problem);
        }
    }

    void decodeMesh(BundleView& view, const fb::Bundle& root) {
        const fb::Mesh* mesh = root.mesh();
        if (mesh == nullptr) {
            fail("metadata has no mesh");
        }
        const std::vector<std::uint64_t> positionShape = mesh->positions() != nullptr
                                                             ? shapeOf(*mesh->positions())
                                                             : std::vector<std::uint64_t>{};
        if (mesh->positions() != nullptr &&
            (positionShape.size() != 2 || positionShape[0] == 0 || positionShape[1] != 3)) {
            fail("mesh positions: shape " + shapeText(positionShape) + ", expected [vertices, 3]");
        }
        const std::uint64_t vertices = positionShape.empty() ? 1 : positionShape[0];
        const std::vector<std::uint64_t> indexShape =
            mesh->indices() != nullptr ? shapeOf(*mesh->indices()) : std::vector<std::uint64_t>{};
        if (mesh->indices() != nullptr &&
            (indexShape.size() != 2 || indexShape[0] == 0 || indexShape[1] != 3)) {
            fail("mesh indices: shape " + shapeText(indexShape) + ", expected [triangles, 3]");
        }
        const std::uint64_t triangles = indexShape.empty() ? 1 : indexShape[0];
        MeshView& m = view.mesh_;
        m.positions = typed<float>(mesh->positions(), "mesh positions", {fb::ElementType::Float32},
                                   {vertices, 3});
        m.normals = typed<float>(mesh->normals(), "mesh normals", {fb::ElementType::Float32},
                                 {vertices, 3});
        m.uvs = typed<float>(mesh->uvs(), "mesh uvs", {fb::ElementType::Float32}, {vertices, 2});
        m.indices = typed<std::uint32_t>(mesh->indices(), "mesh indices", {fb::ElementType::UInt32},
                                         {triangles, 3});
        if (const std::string problem = checkMeshIndices(m.indices, vertices); !problem.empty()) {
            fail(problem);
        }
    }

    void decodeTextures(BundleView& view, const fb::Bundle& root) {
        const fb::Textures* textures = root.textures();
        if (textures == nullptr) {
            fail("metadata has no textures");
        }
        const std::uint32_t width = textures->width();
        const std::uint32_t height = textures->height();
        if (!textureSizeFits(width, height)) {
            fail("textures: " + std::to_string(width) + " x " + std::to_string(height) +
                 (width == 0 || height == 0
                      ? " is empty"
                      : " exceeds the 4096 x 4096 limit of GLES 3.1 on the Raspberry Pi"));
        }
        view.textureWidth_ = static_cast<int>(width);
        view.textureHeight_ = static_cast<int>(height);
        view.textureWrapsU_ = textures->wrap_u();
        const auto* regions = textures->regions();
        if (regions == nullptr || regions->size() == 0) {
            fail("textures: no regions");
        }
        if (!regionCountFits(regions->size())) {
            fail("textures: " + std::to_string(regions->size()) + " regions, more than " +
                 std::to_string(kMaxBundleRegions));
        }
        const int coefficients = view.model_.coefficientsPerTexel();
        for (flatbuffers::uoffset_t r = 0; r < regions->size(); ++r) {
            const fb::Region* region = regions->Get(r);
            if (region == nullptr) {
                fail("textures: region " + std::to_string(r) + " missing");
            }
            RegionView regionView;
            regionView.name = stringOf(region->name());
            const std::string what =
                "region " + std::to_string(r) + " " + quoted(regionView.name) + " coefficients";
            regionView.coefficients =
                decodeMap(region->coefficients(), what, coefficients, width, height);
            view.regions_.push_back(regionView);
        }
        if (textures->composed() != nullptr) {
            view.composed_ = decodeMap(textures->composed(), "composed coefficients", coefficients,
                                       width, height);
        }
        if (const auto* presets = textures->presets(); presets != nullptr) {
            std::set<std::string_view> names;
            for (flatbuffers::uoffset_t p = 0; p < presets->size(); ++p) {
                view.presets_.push_back(
                    decodePreset(presets->Get(p), p, regions->size(), width, height, names));
            }
        }
    }

    CoefficientMapView decodeMap(const fb::CoefficientMap* map, const std::string& what,
                                 int coefficients, std::uint32_t width, std::uint32_t height) {
        if (map == nullptr) {
            fail(what + " missing");
        }
        const auto count = static_cast<std::uint32_t>(coefficients);
        CoefficientMapView view;
        if (map->encoding_type() == fb::CoefficientEncoding::FullCoefficients) {
            const fb::FullCoefficients* full = map->encoding_as_FullCoefficients();
            if (full == nullptr) {
                fail(what + ": full encoding without its table");
            }
            view.encoding = CoefficientEncoding::kFull;
            view.layers =
                halfLayers(full->layers(), what + " layers", layersFor(count), width, height);
        } else if (map->encoding_type() == fb::CoefficientEncoding::LowRankCoefficients) {
            const fb::LowRankCoefficients* lowRank = map->encoding_as_LowRankCoefficients();
            if (lowRank == nullptr) {
                fail(what + ": low-rank encoding without its table");
            }
            view.encoding = CoefficientEncoding::kLowRank;
            const std::uint32_t rank = lowRank->rank();
            if (const std::string problem = checkRank(what, rank, count); !problem.empty()) {
                fail(problem);
            }
            view.rank = static_cast<int>(rank);
            view.mean = floats(lowRank->mean(), what + " mean", count);
            view.basis = floats(lowRank->basis(), what + " basis", std::uint64_t{rank} * count);
            view.layers =
                halfLayers(lowRank->weights(), what + " weights", layersFor(rank), width, height);
        } else {
            fail(what + ": encoding " + std::to_string(static_cast<int>(map->encoding_type())) +
                 " is neither full nor low-rank");
        }
        // 1.2's relief; absent in older bundles (and optional in newer ones).
        if (map->detail_normals() != nullptr) {
            view.detailNormals =
                typed<std::uint16_t>(map->detail_normals(), what + " detail normals",
                                     {fb::ElementType::Float16}, {height, width, 2});
        }
        return view;
    }

    WeightPresetView decodePreset(const fb::WeightPreset* preset, flatbuffers::uoffset_t index,
                                  std::uint32_t regions, std::uint32_t width, std::uint32_t height,
                                  std::set<std::string_view>& names) {
        const std::string where = "preset " + std::to_string(index);
        if (preset == nullptr) {
            fail(where + " missing");
        }
        WeightPresetView view;
        view.name = stringOf(preset->name());
        if (view.name.empty()) {
            fail(where + " has no name");
        }
        if (!names.insert(view.name).second) {
            fail(where + ": another preset is also named " + quoted(view.name));
        }
        view.layers = static_cast<int>(regions);
        const std::string what = where + " " + quoted(view.name) + " alpha";
        const fb::Payload* alpha = preset->alpha();
        const std::span<const std::byte> bytes =
            payload(alpha, what, {fb::ElementType::UInt8, fb::ElementType::Float16},
                    {regions, height, width});
        if (alpha != nullptr && alpha->element_type() == fb::ElementType::UInt8) {
            view.encoding = AlphaEncoding::kUnorm8;
            view.unorm8 = as<std::uint8_t>(bytes);
        } else {
            view.encoding = AlphaEncoding::kFloat16;
            view.halves = as<std::uint16_t>(bytes);
        }
        return view;
    }

    HalfLayers halfLayers(const fb::Payload* layers, const std::string& what, std::uint32_t count,
                          std::uint32_t width, std::uint32_t height) {
        HalfLayers view;
        view.layers = static_cast<int>(count);
        view.width = static_cast<int>(width);
        view.height = static_cast<int>(height);
        view.halves = typed<std::uint16_t>(layers, what, {fb::ElementType::Float16},
                                           {count, height, width, 4});
        return view;
    }

    // A float vector inside the metadata (already verified in bounds and aligned).
    std::span<const float> floats(const flatbuffers::Vector<float>* values, const std::string& what,
                                  std::uint64_t expected) {
        const std::uint64_t size = values != nullptr ? values->size() : 0;
        if (size != expected) {
            fail(what + ": " + std::to_string(size) + " values, expected " +
                 std::to_string(expected));
        }
        const std::span<const float> span(values->data(), values->size());
        for (std::size_t i = 0; i < span.size(); ++i) {
            if (!std::isfinite(span[i])) {
                fail(what + ": value " + std::to_string(i) + " is not finite");
            }
        }
        return span;
    }

    template <typename T>
    static std::span<const T> as(std::span<const std::byte> bytes) {
        return {reinterpret_cast<const T*>(bytes.data()), bytes.size() / sizeof(T)};
    }

    template <typename T>
    std::span<const T> typed(const fb::Payload* reference, const std::string& what,
                             std::initializer_list<fb::ElementType> types,
                             const std::vector<std::uint64_t>& shape) {
        return as<T>(payload(reference, what, types, shape));
    }

    // Checks a payload reference against what the field needs — element type, shape, size —
    // and against the file — 64-byte alignment, past the metadata, inside the file.
    std::span<const std::byte> payload(const fb::Payload* reference, const std::string& what,
                                       std::initializer_list<fb::ElementType> types,
                                       const std::vector<std::uint64_t>& shape) {
        if (reference == nullptr) {
            fail(what + " missing");
        }
        const fb::ElementType type = reference->element_type();
        bool allowed = false;
        std::string expectedTypes;
        for (fb::ElementType t : types) {
            allowed = allowed || t == type;
            expectedTypes += (expectedTypes.empty() ? "" : " or ") + typeName(t);
        }
        if (!allowed) {
            fail(what + ": element type " + typeName(type) + ", expected " + expectedTypes);
        }
        const std::vector<std::uint64_t> actualShape = shapeOf(*reference);
        if (actualShape != shape) {
            fail(what + ": shape " + shapeText(actualShape) + ", expected " + shapeText(shape));
        }
        // No overflow: the shape equals the expected one, whose dimensions are bounded (at
        // most 2^32 · 3 · 4 bytes for a mesh array, 256 · 4096 · 4096 · 4 · 2 for a texture).
        std::uint64_t needed = elementSize(type);
        for (std::uint64_t dim : shape) {
            needed *= dim;
        }
        const std::uint64_t offset = reference->offset();
        const std::uint64_t size = reference->size();
        if (size != needed) {
            fail(what + ": " + std::to_string(size) + " bytes, shape " + shapeText(shape) + " of " +
                 typeName(type) + " needs " + std::to_string(needed));
        }
        if (offset % kBundlePayloadAlignment != 0) {
            fail(what + ": payload at offset " + std::to_string(offset) +
                 " is not 64-byte aligned");
        }
        if (offset < payloadBegin_) {
            fail(what + ": payload at offset " + std::to_string(offset) +
                 " overlaps the header or metadata (they end at " + std::to_string(payloadBegin_) +
                 ")");
        }
        if (offset > bytes_.size() || size > bytes_.size() - offset) {
            fail(what + ": payload of " + std::to_string(size) + " bytes at offset " +
                 std::to_string(offset) + " runs past the end of the file (" +
                 std::to_string(bytes_.size()) + " bytes)");
        }
        return bytes_.subspan(static_cast<std::size_t>(offset), static_cast<std::size_t>(size));
    }

    std::span<const std::byte> bytes_;
    const std::string& name_;
    std::uint64_t payloadBegin_ = 0;
};

BundleView BundleView::parse(std::span<const std::byte> bytes, const std::string& name,
                             const BundleOpenOptions& options) {
    if (reinterpret_cast<std::uintptr_t>(bytes.data()) % kBundlePayloadAlignment != 0) {
        throw std::invalid_argument("BundleView::parse: the bytes of " + name +
                                    " are not 64-byte aligned");
    }
    return BundleDecoder(bytes, name).decode(options);
}

void BundleView::verifyChecksum() {
    const std::uint32_t actual = bundleChecksum(bytes_.subspan(kBundleHeaderSize));
    if (actual != header_.checksum) {
        throw BundleError(name_, "checksum mismatch: header says " + hex32(header_.checksum) +
                                     ", contents give " + hex32(actual));
    }
    checksumVerified_ = true;
}

}  // namespace vpe::proto
