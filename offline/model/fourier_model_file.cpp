// SPDX-License-Identifier: MIT
// Model file I/O with OpenImageIO's OpenEXR plugin.
#include "vpe/model/fourier_model_file.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <cpuid.h>
#include <immintrin.h>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/model/light_transport.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::model {

namespace {

constexpr const char* kFormatName = "vpe-fourier-brdf";
constexpr int kFormatVersion = 1;
constexpr const char* kColour = "RGB";
constexpr const char* kAxis = "XYZ";

// "transport.t07.G": term 7 of the green channel's T. Models written before T had colour
// carry one grey T, "transport.t07".
std::string greyTransportName(int term) {
    return std::string("transport.t") + (term < 10 ? "0" : "") + std::to_string(term);
}
std::string transportName(int term, int channel) {
    return greyTransportName(term) + "." + kColour[channel];
}

// Every channel of the file, in the order the rows are packed.
std::vector<std::string> channelNames(const ModelInfo& info) {
    std::vector<std::string> names;
    const int coefficients = info.coefficientCount();
    const bool withTransport = info.hasTransport();
    const bool withDetail = info.detailNormals;
    for (int k = 0; k < coefficients; ++k) {
        for (int c = 0; c < 3; ++c) {
            names.push_back(coefficientName(info, k) + "." + kColour[c]);
        }
    }
    for (int a = 0; a < 3; ++a) {
        names.push_back(std::string("normal.") + kAxis[a]);
    }
    for (int c = 0; c < 3; ++c) {
        names.push_back(std::string("rms.") + kColour[c]);
    }
    names.push_back("valid");
    if (withTransport) {
        for (int t = 0; t < kTransportTerms; ++t) {
            for (int c = 0; c < kTransportChannels; ++c) {
                names.push_back(transportName(t, c));
            }
        }
    }
    if (withDetail) {
        for (int a = 0; a < 3; ++a) {
            names.push_back(std::string("detail.") + kAxis[a]);
        }
    }
    return names;
}

// No compression: half-float coefficients are noise-like in their low bits, so lossless
// compressors gain only a factor of two at a large cost in CPU on the machine that also fits
// or quilts. Measured, two 2048² 66-channel half maps written by `vpe quilt` (docs/model-file.md):
// none 1171 MB, RLE 1038 MB, PIZ 929 MB, ZIP / ZIPS 558 MB, PXR24 583 MB, each compressor
// 1.4–2.5× the uncompressed write time. Uncompressed half is still half the size of the
// float, ZIPS-compressed file it replaces (1111 MB for a 2048² fit).
constexpr const char* kCompression = "none";

// The largest finite half float; values up to 65520 round to it, beyond to infinity.
constexpr float kHalfMax = 65504.0f;

// Half floats, rounded to nearest even as Imath (OpenEXR's half) rounds; true when every
// value stayed finite. F16C converts eight at a time where the CPU has it (the same rounding,
// bit for bit): OpenImageIO's one-value-at-a-time conversion on the calling thread cost more
// than writing the file. Measured against Imath's own imath_float_to_half on 76.5 M normal
// values (this build targets baseline x86-64, so Imath takes its scalar path): 0.41 vs
// 2.52 ns a value, identical bits; a 2048² fit converts 306 M values, so Imath alone would
// add ~0.4 s of wall time on two threads to a 0.8 s write phase.
__attribute__((target("avx2,f16c"))) bool toHalfF16c(const float* in, std::uint16_t* out,
                                                     std::size_t n) {
    constexpr int kRound = _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC;
    const __m128i exponent = _mm_set1_epi16(0x7c00);
    __m128i overflow = _mm_setzero_si128();
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m128i h = _mm256_cvtps_ph(_mm256_loadu_ps(in + i), kRound);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), h);
        overflow = _mm_or_si128(overflow, _mm_cmpeq_epi16(_mm_and_si128(h, exponent), exponent));
    }
    if (i < n) {  // the last 1–7 values, through a zero-padded vector
        alignas(32) float tail[8] = {};
        alignas(16) std::uint16_t halves[8];
        std::copy(in + i, in + n, tail);
        const __m128i h = _mm256_cvtps_ph(_mm256_load_ps(tail), kRound);
        _mm_store_si128(reinterpret_cast<__m128i*>(halves), h);
        overflow = _mm_or_si128(overflow, _mm_cmpeq_epi16(_mm_and_si128(h, exponent), exponent));
        std::copy(halves, halves + (n - i), out + i);
    }
    return _mm_testz_si128(overflow, overflow) != 0;
}

bool toHalfPortable(const float* in, std::uint16_t* out, std::size_t n) {
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = imath_float_to_half(in[i]);
        finite &= (out[i] & 0x7c00) != 0x7c00;
    }
    return finite;
}

bool toHalf(const float* in, std::uint16_t* out, std::size_t n) {
    // GCC's __builtin_cpu_supports knows "f16c", clang 14's does not: CPUID leaf 1 says it.
    static const bool f16c = [] {
        unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
        return __builtin_cpu_supports("avx2") && __get_cpuid(1, &eax, &ebx, &ecx, &edx) != 0 &&
               (ecx & bit_F16C) != 0;
    }();
    return f16c ? toHalfF16c(in, out, n) : toHalfPortable(in, out, n);
}

// vpeLightIntensities: x, y, z, intensity per light (absent: the lights as stated).
std::vector<capture::LightIntensity> readLightIntensities(const OIIO::ImageSpec& spec,
                                                          const std::filesystem::path& path) {
    const OIIO::ParamValue* attribute = spec.find_attribute("vpeLightIntensities");
    if (!attribute) {
        return {};
    }
    const OIIO::TypeDesc type = attribute->type();
    const std::size_t count = static_cast<std::size_t>(attribute->nvalues()) * type.aggregate *
                              static_cast<std::size_t>(std::max(type.arraylen, 1));
    if (type.basetype != OIIO::TypeDesc::FLOAT || count == 0 || count % 4 != 0) {
        throw common::InputError(path, "vpeLightIntensities must hold 4 floats per light");
    }
    const auto* values = static_cast<const float*>(attribute->data());
    std::vector<capture::LightIntensity> table;
    for (std::size_t i = 0; i < count; i += 4) {
        const proto::Vec3d direction{values[i], values[i + 1], values[i + 2]};
        const double length = std::sqrt(proto::dot(direction, direction));
        const double intensity = values[i + 3];
        if (!(std::fabs(length - 1) < 1e-3) || !(intensity > 0) || !std::isfinite(intensity)) {
            throw common::InputError(path,
                                     "vpeLightIntensities entry " + std::to_string(i / 4) +
                                         " is not a unit direction with a positive intensity");
        }
        table.push_back({direction, intensity});
    }
    return table;
}

}  // namespace

const char* storageName(ModelStorage storage) {
    return storage == ModelStorage::kHalf ? "half" : "float";
}

ModelInfo fourierModelInfo(int width, int height, int harmonics, double lambda, int samples) {
    ModelInfo info;
    info.width = width;
    info.height = height;
    info.harmonics = harmonics;
    info.lambda = lambda;
    info.samples = samples;
    return info;
}

std::string coefficientName(int index) {
    if (index == proto::kLambertIndex) {
        return "kd";
    }
    if (index == proto::kConstantIndex) {
        return "a0";
    }
    return (index % 2 == 0 ? "a" : "b") + std::to_string(proto::harmonicOf(index));
}

std::string coefficientName(const ModelInfo& info, int index) {
    if (info.isBrdf()) {
        return coefficientName(index);
    }
    return (index < 10 ? "c0" : "c") + std::to_string(index);
}

std::optional<RtiBasis> ModelInfo::rtiBasis() const {
    if (isBrdf()) {
        return std::nullopt;
    }
    return RtiBasis::parse(variant + std::to_string(terms));
}

int ModelInfo::coefficientCount() const {
    return isBrdf() ? proto::coefficientCount(harmonics) : terms;
}

void ModelRows::resize(int w, int r, int k, bool withTransport, bool withDetail) {
    width = w;
    rows = r;
    coefficients = k;
    const std::size_t pixels = static_cast<std::size_t>(w) * r;
    coefficient.assign(pixels * 3 * k, 0.0f);
    normal.assign(pixels * 3, 0.0f);
    rms.assign(pixels * 3, 0.0f);
    valid.assign(pixels, 0);
    transport.assign(withTransport ? pixels * kTransportValues : 0, 0.0f);
    detail.assign(withDetail ? pixels * 3 : 0, 0.0f);
    for (std::size_t p = 0; p < detail.size(); p += 3) {
        detail[p + 2] = 1.0f;  // flat
    }
}

// Rows packed in the file's channel order, as half or float, waiting to be written.
struct PackedRows {
    int rowBegin = 0;
    int rows = 0;
    std::vector<float> floats;          // float storage
    std::vector<std::uint16_t> halves;  // half storage
};

struct ModelWriter::Impl {
    std::filesystem::path path;
    proto::AtomicFile output;
    std::unique_ptr<OIIO::ImageOutput> image;
    std::vector<std::string> names;
    int channels = 0;
    int coefficients = 0;
    bool transport = false;
    bool detail = false;
    bool half = false;
    unsigned threads = 1;

    // The writing thread: it hands rows to OpenImageIO (OpenEXR's copy, compression and
    // write) while the caller fits or quilts the next band, instead of the caller waiting.
    std::thread writer;
    std::mutex mutex;
    std::condition_variable changed;
    PackedRows filling;     // the caller's
    PackedRows queued;      // the writer's, when `pending`
    bool pending = false;   // guarded by mutex
    bool stopping = false;  // guarded by mutex
    std::string failure;    // guarded by mutex: the writer's error, if any

    Impl(const std::filesystem::path& p) : path(p), output(p) {}

    ~Impl() { stopWriter(); }

    void startWriter() {
        writer = std::thread([this] { writeQueued(); });
    }

    void writeQueued() {
        std::unique_lock lock(mutex);
        for (;;) {
            changed.wait(lock, [this] { return pending || stopping; });
            if (!pending) {
                return;
            }
            lock.unlock();
            const bool written =
                half ? image->write_scanlines(queued.rowBegin, queued.rowBegin + queued.rows, 0,
                                              OIIO::TypeDesc::HALF, queued.halves.data())
                     : image->write_scanlines(queued.rowBegin, queued.rowBegin + queued.rows, 0,
                                              OIIO::TypeDesc::FLOAT, queued.floats.data());
            lock.lock();
            if (!written && failure.empty()) {
                failure = "cannot write model rows: " + image->geterror();
            }
            pending = false;
            changed.notify_all();
        }
    }

    // Waits until the writer has nothing queued; throws its error, if it had one.
    void waitForWriter() {
        std::unique_lock lock(mutex);
        changed.wait(lock, [this] { return !pending; });
        if (!failure.empty()) {
            throw common::InputError(path, failure);
        }
    }

    void stopWriter() {
        if (!writer.joinable()) {
            return;
        }
        {
            std::lock_guard lock(mutex);
            stopping = true;
        }
        changed.notify_all();
        writer.join();
    }

    // Pixel p of `rows` in the file's channel order.
    void pack(const ModelRows& rows, std::size_t p, float* out) const {
        const int k = coefficients;
        for (int i = 0; i < k; ++i) {
            for (int c = 0; c < 3; ++c) {
                *out++ = rows.coefficient[(p * 3 + c) * k + i];
            }
        }
        for (int a = 0; a < 3; ++a) {
            *out++ = rows.normal[p * 3 + a];
        }
        for (int c = 0; c < 3; ++c) {
            *out++ = rows.rms[p * 3 + c];
        }
        *out++ = rows.valid[p] ? 1.0f : 0.0f;
        if (transport) {
            for (int t = 0; t < kTransportTerms; ++t) {
                for (int c = 0; c < kTransportChannels; ++c) {
                    *out++ = rows.transport[p * kTransportValues + c * kTransportTerms + t];
                }
            }
        }
        if (detail) {
            for (int a = 0; a < 3; ++a) {
                *out++ = rows.detail.empty() ? (a == 2 ? 1.0f : 0.0f) : rows.detail[p * 3 + a];
            }
        }
    }
};

ModelWriter::ModelWriter(const std::filesystem::path& path, const ModelInfo& info, unsigned threads)
    : impl_(std::make_unique<Impl>(path)) {
    impl_->threads = std::max(threads, 1u);
    if (path.extension() != ".exr") {
        throw common::InputError(path, "the model file must have the .exr extension");
    }
    if (!info.isBrdf() && !info.rtiBasis()) {
        throw common::InputError(path, "unknown model variant '" + info.variant + "' with " +
                                           std::to_string(info.terms) + " terms");
    }
    impl_->coefficients = info.coefficientCount();
    impl_->transport = info.hasTransport();
    impl_->detail = info.detailNormals;
    impl_->names = channelNames(info);
    impl_->channels = static_cast<int>(impl_->names.size());
    impl_->half = info.storage == ModelStorage::kHalf;
    OIIO::ImageSpec spec(info.width, info.height, impl_->channels,
                         impl_->half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = impl_->names;
    spec.alpha_channel = -1;
    spec.attribute("compression", kCompression);
    spec.attribute("vpeFormat", kFormatName);
    spec.attribute("vpeFormatVersion", kFormatVersion);
    spec.attribute("vpeHarmonics", info.harmonics);
    spec.attribute("vpeLambda", static_cast<float>(info.lambda));
    spec.attribute("vpeSamples", info.samples);
    spec.attribute("vpeVariant", info.variant);
    if (!info.isBrdf()) {
        spec.attribute("vpeTerms", info.terms);
    }
    spec.attribute("vpeCapture", info.capture);
    spec.attribute("vpeFieldOfView", static_cast<float>(info.calibration.fieldOfViewDegrees));
    spec.attribute("vpeLightDistance", static_cast<float>(info.calibration.lightDistance));
    if (info.calibration.responseGamma > 0) {
        spec.attribute("vpeResponseGamma", static_cast<float>(info.calibration.responseGamma));
    }
    if (!info.calibration.lightIntensities.empty()) {
        // x, y, z, intensity per light.
        std::vector<float> table;
        for (const capture::LightIntensity& entry : info.calibration.lightIntensities) {
            table.insert(
                table.end(),
                {static_cast<float>(entry.direction.x), static_cast<float>(entry.direction.y),
                 static_cast<float>(entry.direction.z), static_cast<float>(entry.intensity)});
        }
        spec.attribute("vpeLightIntensities",
                       OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, static_cast<int>(table.size())),
                       table.data());
    }
    if (info.texelMm > 0) {
        spec.attribute("vpeTexelMm", static_cast<float>(info.texelMm));
    }
    if (info.tilesU) {
        spec.attribute("vpeTilesU", 1);
    }
    spec.attribute("vpeUnits", info.isBrdf()
                                   ? "linear radiance per unit light irradiance; layout "
                                     "kd,a0,a1,b1,...; see proto/MODEL.md"
                                   : "stored image values (code / full scale) of the RTI basis "
                                     "named by vpeVariant and vpeTerms; see docs/model-file.md");
    impl_->image = OIIO::ImageOutput::create("exr");
    if (!impl_->image || !impl_->image->open(impl_->output.temporaryPath().string(), spec)) {
        throw common::InputError(path,
                                 "cannot write model file: " +
                                     (impl_->image ? impl_->image->geterror() : OIIO::geterror()));
    }
    impl_->startWriter();
}

ModelWriter::~ModelWriter() = default;

void ModelWriter::writeRows(int rowBegin, const ModelRows& rows) {
    const auto channels = static_cast<std::size_t>(impl_->channels);
    const auto width = static_cast<std::size_t>(rows.width);
    const std::size_t values = width * static_cast<std::size_t>(rows.rows) * channels;
    PackedRows& packed = impl_->filling;
    packed.rowBegin = rowBegin;
    packed.rows = rows.rows;
    // Rows are packed (and converted) on all threads: one thread packing a 66-channel band
    // left the other idle for a third of the write.
    std::atomic<int> overflowRow{rows.rows};
    if (impl_->half) {
        packed.halves.resize(values);
        common::parallelFor(
            static_cast<std::size_t>(rows.rows), 1, impl_->threads,
            [&](std::size_t begin, std::size_t end) {
                std::vector<float> line(width * channels);
                for (std::size_t r = begin; r < end; ++r) {
                    for (std::size_t x = 0; x < width; ++x) {
                        impl_->pack(rows, r * width + x, line.data() + x * channels);
                    }
                    if (!toHalf(line.data(), packed.halves.data() + r * width * channels,
                                line.size())) {
                        int expected = overflowRow.load();
                        while (static_cast<int>(r) < expected &&
                               !overflowRow.compare_exchange_weak(expected, static_cast<int>(r))) {
                        }
                    }
                }
            });
        if (overflowRow.load() < rows.rows) {
            reportHalfOverflow(rowBegin, overflowRow.load(), rows);
        }
    } else {
        packed.floats.resize(values);
        common::parallelFor(static_cast<std::size_t>(rows.rows), 1, impl_->threads,
                            [&](std::size_t begin, std::size_t end) {
                                for (std::size_t p = begin * width; p < end * width; ++p) {
                                    impl_->pack(rows, p, packed.floats.data() + p * channels);
                                }
                            });
    }
    // Hand the rows to the writer once it has written the previous ones.
    impl_->waitForWriter();
    {
        std::lock_guard lock(impl_->mutex);
        std::swap(impl_->filling, impl_->queued);
        impl_->pending = true;
    }
    impl_->changed.notify_all();
}

void ModelWriter::reportHalfOverflow(int rowBegin, int row, const ModelRows& rows) const {
    const auto channels = static_cast<std::size_t>(impl_->channels);
    std::vector<float> pixel(channels);
    for (int x = 0; x < rows.width; ++x) {
        impl_->pack(rows, rows.pixel(row, x), pixel.data());
        for (std::size_t c = 0; c < channels; ++c) {
            if (!(std::fabs(pixel[c]) <= kHalfMax)) {
                throw common::InputError(
                    impl_->path, "pixel (" + std::to_string(x) + ", " +
                                     std::to_string(rowBegin + row) + "): " + impl_->names[c] +
                                     " = " + std::to_string(pixel[c]) +
                                     " is beyond the half-float range (±65504); write it with "
                                     "--storage float");
            }
        }
    }
    throw std::logic_error("ModelWriter: a half-float overflow that no value explains");
}

void ModelWriter::finish() {
    impl_->waitForWriter();
    impl_->stopWriter();
    if (!impl_->image->close()) {
        throw common::InputError(impl_->path,
                                 "cannot finish model file: " + impl_->image->geterror());
    }
    impl_->output.commit();
}

struct ModelReader::Impl {
    std::filesystem::path path;
    std::unique_ptr<OIIO::ImageInput> image;
    ModelInfo info;
    int channels = 0;
    std::vector<int> coefficientChannel;  // [k * 3 + c] → file channel
    int normalChannel[3] = {};
    int rmsChannel[3] = {};
    int validChannel = 0;
    std::vector<int> transportChannel;  // empty without transport
    std::vector<int> detailChannel;     // empty without a relief
    std::vector<float> scanlines;
};

ModelReader::ModelReader(const std::filesystem::path& path, ModelKinds accepted)
    : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    impl_->image = OIIO::ImageInput::open(path.string());
    if (!impl_->image) {
        if (!std::filesystem::exists(path)) {
            throw common::InputError(path, "no such model file");
        }
        throw common::InputError(path, "cannot read model file: " + OIIO::geterror());
    }
    const OIIO::ImageSpec& spec = impl_->image->spec();
    if (spec.get_string_attribute("vpeFormat") != kFormatName) {
        throw common::InputError(path, "not a vpe model file (no vpeFormat attribute)");
    }
    const int version = spec.get_int_attribute("vpeFormatVersion", -1);
    if (version != kFormatVersion) {
        throw common::InputError(path, "model format version " + std::to_string(version) +
                                           " is not supported (expected " +
                                           std::to_string(kFormatVersion) + ")");
    }
    ModelInfo& info = impl_->info;
    info.width = spec.width;
    info.height = spec.height;
    info.harmonics = spec.get_int_attribute("vpeHarmonics", -1);
    info.lambda = spec.get_float_attribute("vpeLambda", 0.0f);
    info.samples = spec.get_int_attribute("vpeSamples", 0);
    info.variant = spec.get_string_attribute("vpeVariant", "paper");
    info.terms = spec.get_int_attribute("vpeTerms", 0);
    if (!info.isBrdf() && !info.rtiBasis()) {
        throw common::InputError(path, "unknown model variant '" + info.variant + "'");
    }
    if (!info.isBrdf() && accepted == ModelKinds::kBrdf) {
        throw common::InputError(path,
                                 "is an RTI basis fit (" + info.rtiBasis()->name() +
                                     "), not a Fourier BRDF: use a model from vpe fit --model "
                                     "paper|extended");
    }
    info.capture = spec.get_string_attribute("vpeCapture");
    info.calibration.fieldOfViewDegrees = spec.get_float_attribute("vpeFieldOfView", 0.0f);
    info.calibration.lightDistance = spec.get_float_attribute("vpeLightDistance", 0.0f);
    info.calibration.responseGamma = spec.get_float_attribute("vpeResponseGamma", 0.0f);
    info.calibration.lightIntensities = readLightIntensities(spec, path);
    info.texelMm = spec.get_float_attribute("vpeTexelMm", 0.0f);
    info.tilesU = spec.get_int_attribute("vpeTilesU", 0) != 0;
    if (!(info.calibration.fieldOfViewDegrees >= 0 && info.calibration.fieldOfViewDegrees < 180 &&
          info.calibration.lightDistance >= 0 && info.calibration.responseGamma >= 0 &&
          info.calibration.responseGamma <= 10)) {
        throw common::InputError(path, "geometry calibration out of range");
    }
    if (!(info.texelMm >= 0) || !std::isfinite(info.texelMm)) {
        throw common::InputError(path, "vpeTexelMm must be a size in millimetres ≥ 0");
    }
    if (info.harmonics < 0 || info.harmonics > proto::kMaxHarmonics) {
        throw common::InputError(
            path, "harmonic count " + std::to_string(info.harmonics) + " is out of range");
    }
    impl_->channels = spec.nchannels;
    auto find = [&](const std::string& name) {
        const auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), name);
        if (it == spec.channelnames.end()) {
            throw common::InputError(path, "missing channel '" + name + "'");
        }
        return static_cast<int>(it - spec.channelnames.begin());
    };
    const int k = info.coefficientCount();
    impl_->coefficientChannel.resize(static_cast<std::size_t>(k) * 3);
    for (int i = 0; i < k; ++i) {
        for (int c = 0; c < 3; ++c) {
            impl_->coefficientChannel[static_cast<std::size_t>(i) * 3 + c] =
                find(coefficientName(info, i) + "." + kColour[c]);
        }
    }
    for (int a = 0; a < 3; ++a) {
        impl_->normalChannel[a] = find(std::string("normal.") + kAxis[a]);
        impl_->rmsChannel[a] = find(std::string("rms.") + kColour[a]);
    }
    impl_->validChannel = find("valid");
    info.storage = spec.channelformat(impl_->coefficientChannel[0]) == OIIO::TypeDesc::HALF
                       ? ModelStorage::kHalf
                       : ModelStorage::kFloat;
    if (info.hasTransport()) {
        // [channel][term], as ModelRows holds it; a grey T serves all three channels.
        const bool grey = std::find(spec.channelnames.begin(), spec.channelnames.end(),
                                    greyTransportName(0)) != spec.channelnames.end();
        for (int c = 0; c < kTransportChannels; ++c) {
            for (int t = 0; t < kTransportTerms; ++t) {
                impl_->transportChannel.push_back(
                    find(grey ? greyTransportName(t) : transportName(t, c)));
            }
        }
    }
    // Optional: models written before the relief was carried have none.
    info.detailNormals = std::find(spec.channelnames.begin(), spec.channelnames.end(),
                                   "detail.X") != spec.channelnames.end();
    if (info.detailNormals) {
        for (int a = 0; a < 3; ++a) {
            impl_->detailChannel.push_back(find(std::string("detail.") + kAxis[a]));
        }
    }
}

ModelReader::~ModelReader() = default;

const ModelInfo& ModelReader::info() const {
    return impl_->info;
}

void ModelReader::readRows(int rowBegin, int rows, ModelRows& out) {
    const int k = impl_->info.coefficientCount();
    const int width = impl_->info.width;
    const int channels = impl_->channels;
    out.resize(width, rows, k, !impl_->transportChannel.empty(), !impl_->detailChannel.empty());
    impl_->scanlines.resize(static_cast<std::size_t>(width) * rows * channels);
    if (!impl_->image->read_scanlines(0, 0, rowBegin, rowBegin + rows, 0, 0, channels,
                                      OIIO::TypeDesc::FLOAT, impl_->scanlines.data())) {
        throw common::InputError(impl_->path,
                                 "cannot decode model rows: " + impl_->image->geterror());
    }
    for (int r = 0; r < rows; ++r) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = out.pixel(r, x);
            const float* in = impl_->scanlines.data() + p * channels;
            for (int i = 0; i < k; ++i) {
                for (int c = 0; c < 3; ++c) {
                    out.coefficient[(p * 3 + c) * k + i] =
                        in[impl_->coefficientChannel[static_cast<std::size_t>(i) * 3 + c]];
                }
            }
            for (int a = 0; a < 3; ++a) {
                out.normal[p * 3 + a] = in[impl_->normalChannel[a]];
                out.rms[p * 3 + a] = in[impl_->rmsChannel[a]];
            }
            out.valid[p] = in[impl_->validChannel] > 0.5f ? 1 : 0;
            for (std::size_t t = 0; t < impl_->transportChannel.size(); ++t) {
                out.transport[p * kTransportValues + t] = in[impl_->transportChannel[t]];
            }
            for (std::size_t a = 0; a < impl_->detailChannel.size(); ++a) {
                out.detail[p * 3 + a] = in[impl_->detailChannel[a]];
            }
        }
    }
}

}  // namespace vpe::model
