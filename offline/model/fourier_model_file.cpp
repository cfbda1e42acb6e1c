// SPDX-License-Identifier: MIT
// Model file I/O with OpenImageIO's OpenEXR plugin.
#include "model/fourier_model_file.h"

#include <algorithm>
#include <cmath>

#include <OpenImageIO/imageio.h>

#include "vpe/proto/fourier_brdf.h"

#include "common/atomic_output.h"
#include "common/input_error.h"
#include "model/light_transport.h"

namespace vpe {

namespace {

constexpr const char* kFormatName = "vpe-fourier-brdf";
constexpr int kFormatVersion = 1;
constexpr const char* kColour = "RGB";
constexpr const char* kAxis = "XYZ";

std::string transportName(int term) {
    return std::string("transport.t") + (term < 10 ? "0" : "") + std::to_string(term);
}

// Every channel of the file, in the order the rows are packed.
std::vector<std::string> channelNames(const ModelInfo& info) {
    std::vector<std::string> names;
    const int coefficients = info.coefficientCount();
    const bool withTransport = info.hasTransport();
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
            names.push_back(transportName(t));
        }
    }
    return names;
}

}  // namespace

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

void ModelRows::resize(int w, int r, int k, bool withTransport) {
    width = w;
    rows = r;
    coefficients = k;
    const std::size_t pixels = static_cast<std::size_t>(w) * r;
    coefficient.assign(pixels * 3 * k, 0.0f);
    normal.assign(pixels * 3, 0.0f);
    rms.assign(pixels * 3, 0.0f);
    valid.assign(pixels, 0);
    transport.assign(withTransport ? pixels * kTransportTerms : 0, 0.0f);
}

struct ModelWriter::Impl {
    std::filesystem::path path;
    AtomicOutput output;
    std::unique_ptr<OIIO::ImageOutput> image;
    int channels = 0;
    int coefficients = 0;
    bool transport = false;
    std::vector<float> scanlines;

    Impl(const std::filesystem::path& p) : path(p), output(p) {}
};

ModelWriter::ModelWriter(const std::filesystem::path& path, const ModelInfo& info)
    : impl_(std::make_unique<Impl>(path)) {
    if (path.extension() != ".exr") {
        throw InputError(path, "the model file must have the .exr extension");
    }
    if (!info.isBrdf() && !info.rtiBasis()) {
        throw InputError(path, "unknown model variant '" + info.variant + "' with " +
                                   std::to_string(info.terms) + " terms");
    }
    impl_->coefficients = info.coefficientCount();
    impl_->transport = info.hasTransport();
    const std::vector<std::string> names = channelNames(info);
    impl_->channels = static_cast<int>(names.size());
    OIIO::ImageSpec spec(info.width, info.height, impl_->channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    // ZIP per scanline: the model is written in bands of ~16 rows, and 16-line ZIP blocks
    // would make each band one block that only one thread can compress (measured on a
    // 2048² model: 16 s instead of 29 s; same size on real models).
    spec.attribute("compression", "zips");
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
        throw InputError(path, "cannot write model file: " +
                                   (impl_->image ? impl_->image->geterror() : OIIO::geterror()));
    }
}

ModelWriter::~ModelWriter() = default;

void ModelWriter::writeRows(int rowBegin, const ModelRows& rows) {
    const int channels = impl_->channels;
    const int k = impl_->coefficients;
    impl_->scanlines.resize(static_cast<std::size_t>(rows.width) * rows.rows * channels);
    for (int r = 0; r < rows.rows; ++r) {
        for (int x = 0; x < rows.width; ++x) {
            const std::size_t p = rows.pixel(r, x);
            float* out = impl_->scanlines.data() + p * channels;
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
            if (impl_->transport) {
                for (int t = 0; t < kTransportTerms; ++t) {
                    *out++ = rows.transport[p * kTransportTerms + t];
                }
            }
        }
    }
    if (!impl_->image->write_scanlines(rowBegin, rowBegin + rows.rows, 0, OIIO::TypeDesc::FLOAT,
                                       impl_->scanlines.data())) {
        throw InputError(impl_->path, "cannot write model rows: " + impl_->image->geterror());
    }
}

void ModelWriter::finish() {
    if (!impl_->image->close()) {
        throw InputError(impl_->path, "cannot finish model file: " + impl_->image->geterror());
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
    std::vector<float> scanlines;
};

ModelReader::ModelReader(const std::filesystem::path& path, ModelKinds accepted)
    : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    impl_->image = OIIO::ImageInput::open(path.string());
    if (!impl_->image) {
        if (!std::filesystem::exists(path)) {
            throw InputError(path, "no such model file");
        }
        throw InputError(path, "cannot read model file: " + OIIO::geterror());
    }
    const OIIO::ImageSpec& spec = impl_->image->spec();
    if (spec.get_string_attribute("vpeFormat") != kFormatName) {
        throw InputError(path, "not a vpe model file (no vpeFormat attribute)");
    }
    const int version = spec.get_int_attribute("vpeFormatVersion", -1);
    if (version != kFormatVersion) {
        throw InputError(path, "model format version " + std::to_string(version) +
                                   " is not supported (expected " + std::to_string(kFormatVersion) +
                                   ")");
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
        throw InputError(path, "unknown model variant '" + info.variant + "'");
    }
    if (!info.isBrdf() && accepted == ModelKinds::kBrdf) {
        throw InputError(path, "is an RTI basis fit (" + info.rtiBasis()->name() +
                                   "), not a Fourier BRDF: use a model from vpe fit --model "
                                   "paper|extended");
    }
    info.capture = spec.get_string_attribute("vpeCapture");
    info.calibration.fieldOfViewDegrees = spec.get_float_attribute("vpeFieldOfView", 0.0f);
    info.calibration.lightDistance = spec.get_float_attribute("vpeLightDistance", 0.0f);
    info.texelMm = spec.get_float_attribute("vpeTexelMm", 0.0f);
    info.tilesU = spec.get_int_attribute("vpeTilesU", 0) != 0;
    if (!(info.calibration.fieldOfViewDegrees >= 0 && info.calibration.fieldOfViewDegrees < 180 &&
          info.calibration.lightDistance >= 0)) {
        throw InputError(path, "geometry calibration out of range");
    }
    if (!(info.texelMm >= 0) || !std::isfinite(info.texelMm)) {
        throw InputError(path, "vpeTexelMm must be a size in millimetres ≥ 0");
    }
    if (info.harmonics < 0 || info.harmonics > proto::kMaxHarmonics) {
        throw InputError(path,
                         "harmonic count " + std::to_string(info.harmonics) + " is out of range");
    }
    impl_->channels = spec.nchannels;
    auto find = [&](const std::string& name) {
        const auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), name);
        if (it == spec.channelnames.end()) {
            throw InputError(path, "missing channel '" + name + "'");
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
    if (info.hasTransport()) {
        for (int t = 0; t < kTransportTerms; ++t) {
            impl_->transportChannel.push_back(find(transportName(t)));
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
    out.resize(width, rows, k, !impl_->transportChannel.empty());
    impl_->scanlines.resize(static_cast<std::size_t>(width) * rows * channels);
    if (!impl_->image->read_scanlines(0, 0, rowBegin, rowBegin + rows, 0, 0, channels,
                                      OIIO::TypeDesc::FLOAT, impl_->scanlines.data())) {
        throw InputError(impl_->path, "cannot decode model rows: " + impl_->image->geterror());
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
                out.transport[p * kTransportTerms + t] = in[impl_->transportChannel[t]];
            }
        }
    }
}

}  // namespace vpe
