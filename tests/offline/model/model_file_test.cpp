// SPDX-License-Identifier: MIT
// The model file: bit-exact round trip, channel names EXR tools see, refusals naming the file.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <Imath/half.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/light_transport.h"
#include "vpe/proto/fourier_brdf.h"

#include "support/test_data.h"

namespace vpe {
namespace {

model::ModelInfo sampleInfo(int width, int height, int harmonics) {
    model::ModelInfo info;
    info.width = width;
    info.height = height;
    info.harmonics = harmonics;
    info.lambda = 0.5;  // exact in float, the attribute's type
    info.samples = 49;
    info.variant = "paper";
    info.capture = "/captures/object1/dirs.lp";
    return info;
}

// Random values over many magnitudes and both signs, so any conversion would show.
model::ModelRows randomRows(int width, int rows, int harmonics, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-20, 20);
    auto value = [&] { return std::ldexp(mantissa(random), exponent(random)); };
    model::ModelRows out;
    out.resize(width, rows, proto::coefficientCount(harmonics));
    for (float& v : out.coefficient) {
        v = value();
    }
    for (float& v : out.normal) {
        v = value();
    }
    for (float& v : out.rms) {
        v = std::fabs(value());
    }
    for (std::size_t i = 0; i < out.valid.size(); ++i) {
        out.valid[i] = (i * 7 + seed) % 3 != 0 ? 1 : 0;
    }
    return out;
}

void writeModel(const std::filesystem::path& path, const model::ModelInfo& info,
                const model::ModelRows& rows) {
    model::ModelWriter writer(path, info);
    // Two bands, as the fitter writes them.
    const int split = info.height / 2;
    model::ModelRows band;
    for (int begin : {0, split}) {
        const int count = begin == 0 ? split : info.height - split;
        band.resize(rows.width, count, rows.coefficients);
        const std::size_t pixels = static_cast<std::size_t>(rows.width) * count;
        const std::size_t first = static_cast<std::size_t>(rows.width) * begin;
        const auto k = static_cast<std::size_t>(rows.coefficients);
        std::copy_n(rows.coefficient.begin() + static_cast<long>(first * 3 * k), pixels * 3 * k,
                    band.coefficient.begin());
        std::copy_n(rows.normal.begin() + static_cast<long>(first * 3), pixels * 3,
                    band.normal.begin());
        std::copy_n(rows.rms.begin() + static_cast<long>(first * 3), pixels * 3, band.rms.begin());
        std::copy_n(rows.valid.begin() + static_cast<long>(first), pixels, band.valid.begin());
        writer.writeRows(begin, band);
    }
    writer.finish();
}

// Random rows over the whole of `info`'s picture, written to `path` as a model and returned
// to compare what is read back with.
model::ModelRows writeRandomModel(const std::filesystem::path& path, const model::ModelInfo& info,
                                  std::uint32_t seed) {
    model::ModelRows rows = randomRows(info.width, info.height, info.harmonics, seed);
    writeModel(path, info, rows);
    return rows;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

std::string inputErrorOf(const std::function<void()>& action) {
    try {
        action();
    } catch (const common::InputError& error) {
        return error.what();
    }
    return "(no InputError)";
}

void writePlainExr(const std::filesystem::path& path, int width, int height,
                   const std::function<void(OIIO::ImageSpec&)>& decorate = {}) {
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
    if (decorate) {
        decorate(spec);
    }
    const std::vector<float> pixels(static_cast<std::size_t>(width) * height * 3, 0.5f);
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), spec) &&
                out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
}

TEST(ModelFile, CoefficientNamesFollowTheInterleavedLayout) {
    const char* const expected[] = {"kd", "a0", "a1", "b1", "a2", "b2"};
    for (int k = 0; k < 6; ++k) {
        EXPECT_EQ(model::coefficientName(k), expected[k]) << k;
    }
    EXPECT_EQ(model::coefficientName(proto::cosineIndex(15)), "a15");
    EXPECT_EQ(model::coefficientName(proto::sineIndex(15)), "b15");
}

TEST(ModelFile, RoundTripIsBitExact) {
    testing::TemporaryFolder folder;
    const model::ModelInfo info = sampleInfo(7, 5, 2);
    const model::ModelRows written = writeRandomModel(folder / "model.exr", info, 3);

    model::ModelReader reader(folder / "model.exr");
    EXPECT_EQ(reader.info().width, info.width);
    EXPECT_EQ(reader.info().height, info.height);
    EXPECT_EQ(reader.info().harmonics, info.harmonics);
    EXPECT_EQ(reader.info().lambda, info.lambda);
    EXPECT_EQ(reader.info().samples, info.samples);
    EXPECT_EQ(reader.info().variant, info.variant);
    EXPECT_EQ(reader.info().capture, info.capture);
    EXPECT_EQ(reader.info().texelMm, 0.0);  // unknown: no attribute
    EXPECT_FALSE(reader.info().tilesU);
    model::ModelRows read;
    reader.readRows(0, info.height, read);
    EXPECT_EQ(read.width, info.width);
    EXPECT_EQ(read.rows, info.height);
    EXPECT_EQ(read.coefficients, 6);
    EXPECT_EQ(reader.info().storage, model::ModelStorage::kFloat);  // the default: exact
    EXPECT_TRUE(sameBits(read.coefficient, written.coefficient));
    EXPECT_TRUE(sameBits(read.normal, written.normal));
    EXPECT_TRUE(sameBits(read.rms, written.rms));
    EXPECT_EQ(read.valid, written.valid);
}

// The capture's texel size and whether the texture tiles in u travel in the header.
TEST(ModelFile, KeepsTheTexelSizeAndTiling) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(4, 3, 1);
    info.texelMm = 0.625;  // exact in float
    info.tilesU = true;
    writeRandomModel(folder / "model.exr", info, 5);
    model::ModelReader reader(folder / "model.exr");
    EXPECT_EQ(reader.info().texelMm, 0.625);
    EXPECT_TRUE(reader.info().tilesU);
}

// The calibration the extended fit found — camera response included — travels with the model:
// vpe eval of another capture from the same rig applies it.
TEST(ModelFile, KeepsTheCaptureCalibration) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(4, 3, 1);
    info.calibration = {12.5, 6.0, 1.4, {{{0.6, 0.0, 0.8}, 0.25}, {{0.0, 0.0, 1.0}, 1.0}}};
    writeRandomModel(folder / "model.exr", info, 5);
    const capture::GeometryCalibration read =
        model::ModelReader(folder / "model.exr").info().calibration;
    EXPECT_EQ(read.fieldOfViewDegrees, 12.5);
    EXPECT_EQ(read.lightDistance, 6.0);
    EXPECT_NEAR(read.responseGamma, 1.4, 1e-6);  // stored as a float attribute
    ASSERT_EQ(read.lightIntensities.size(), 2u);
    EXPECT_NEAR(read.lightIntensities[0].direction.x, 0.6, 1e-6);
    EXPECT_NEAR(read.lightIntensities[0].direction.z, 0.8, 1e-6);
    EXPECT_EQ(read.lightIntensities[0].intensity, 0.25);
    EXPECT_EQ(read.lightIntensities[1].intensity, 1.0);
    // A model without a calibrated response reads as "as the capture states".
    model::ModelInfo plain = sampleInfo(4, 3, 1);
    writeRandomModel(folder / "plain.exr", plain, 5);
    EXPECT_EQ(model::ModelReader(folder / "plain.exr").info().calibration.responseGamma, 0.0);
    EXPECT_TRUE(
        model::ModelReader(folder / "plain.exr").info().calibration.lightIntensities.empty());
}

// A light table that is not 4 floats per light, or holds no unit direction, is a corrupt model.
TEST(ModelFile, RejectsAMalformedLightTable) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(4, 3, 1);
    info.calibration.lightIntensities = {{{3.0, 0.0, 4.0}, 0.5}};  // not a unit direction
    writeRandomModel(folder / "model.exr", info, 5);
    try {
        model::ModelReader reader(folder / "model.exr");
        FAIL() << "read a light table whose direction has length 5";
    } catch (const common::InputError& error) {
        EXPECT_NE(std::string(error.what()).find("vpeLightIntensities"), std::string::npos)
            << error.what();
    }
}

// Half floats round to 11 significant bits: relative error ≤ 2⁻¹¹ for normal numbers
// (|x| ≥ 2⁻¹⁴), absolute ≤ 2⁻²⁵ (half a subnormal step) below: docs/model-file.md.
bool withinHalfTolerance(float read, float written) {
    const double error = std::fabs(static_cast<double>(read) - static_cast<double>(written));
    return error <=
           std::max(std::ldexp(std::fabs(static_cast<double>(written)), -11), std::ldexp(1.0, -25));
}

TEST(ModelFile, RoundTripInHalfIsWithinItsStatedTolerance) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(9, 6, 3);
    info.variant = "extended";  // every kind of channel, the transport too
    info.storage = model::ModelStorage::kHalf;
    // Magnitudes from 2⁻²⁴ (subnormal in half) to 2¹⁵, both signs.
    std::mt19937 random(17);
    std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
    std::uniform_int_distribution<int> exponent(-24, 15);
    auto value = [&] { return std::ldexp(mantissa(random), exponent(random)); };
    model::ModelRows written;
    written.resize(info.width, info.height, proto::coefficientCount(info.harmonics), true);
    for (std::vector<float>* values :
         {&written.coefficient, &written.normal, &written.rms, &written.transport}) {
        for (float& v : *values) {
            v = value();
        }
    }
    for (std::size_t i = 0; i < written.valid.size(); ++i) {
        written.valid[i] = i % 3 != 0 ? 1 : 0;
    }
    {
        model::ModelWriter writer(folder / "model.exr", info);
        writer.writeRows(0, written);
        writer.finish();
    }
    model::ModelReader reader(folder / "model.exr");
    EXPECT_EQ(reader.info().storage, model::ModelStorage::kHalf);
    model::ModelRows read;
    reader.readRows(0, info.height, read);
    for (const auto& [name, a, b] :
         {std::tuple{"coefficient", &read.coefficient, &written.coefficient},
          std::tuple{"normal", &read.normal, &written.normal},
          std::tuple{"rms", &read.rms, &written.rms},
          std::tuple{"transport", &read.transport, &written.transport}}) {
        ASSERT_EQ(a->size(), b->size()) << name;
        std::size_t outside = 0, notImath = 0;
        bool changed = false;
        for (std::size_t i = 0; i < a->size(); ++i) {
            outside += withinHalfTolerance((*a)[i], (*b)[i]) ? 0 : 1;
            // Rounded exactly as OpenEXR's own half type rounds (to nearest even).
            notImath += (*a)[i] == static_cast<float>(Imath::half((*b)[i])) ? 0 : 1;
            changed |= (*a)[i] != (*b)[i];
        }
        EXPECT_EQ(outside, 0u) << name;
        EXPECT_EQ(notImath, 0u) << name;
        EXPECT_TRUE(changed) << name << ": not stored as half";
    }
    EXPECT_EQ(read.valid, written.valid);  // 0 and 1 are exact in half
}

// Models written before T had colour carry one grey T ("transport.t07"); the reader gives it
// to all three channels.
TEST(ModelFile, ReadsAGreyTransportIntoEveryChannel) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(5, 3, 2);
    info.variant = "extended";
    info.storage = model::ModelStorage::kFloat;
    model::ModelRows written = randomRows(info.width, info.height, info.harmonics, 5);
    written.resize(info.width, info.height, written.coefficients, true);
    for (std::size_t i = 0; i < written.transport.size(); ++i) {
        written.transport[i] = static_cast<float>(i) * 0.25f;
    }
    {
        model::ModelWriter writer(folder / "colour.exr", info);
        writer.writeRows(0, written);
        writer.finish();
    }
    // The same file with only the green channel's T, under the grey names.
    {
        const OIIO::ImageBuf colour((folder / "colour.exr").string());
        std::vector<int> order;
        std::vector<std::string> names;
        for (int c = 0; c < colour.nchannels(); ++c) {
            const std::string& name = colour.spec().channelnames[static_cast<std::size_t>(c)];
            if (name.rfind("transport.", 0) != 0) {
                order.push_back(c);
                names.push_back(name);
            } else if (name.back() == 'G') {
                order.push_back(c);
                names.push_back(name.substr(0, name.size() - 2));
            }
        }
        const OIIO::ImageBuf grey =
            OIIO::ImageBufAlgo::channels(colour, static_cast<int>(order.size()), order, {}, names);
        ASSERT_TRUE(grey.write((folder / "grey.exr").string())) << grey.geterror();
    }
    model::ModelReader reader(folder / "grey.exr");
    model::ModelRows read;
    reader.readRows(0, info.height, read);
    ASSERT_EQ(read.transport.size(), written.transport.size());
    for (std::size_t p = 0; p < read.valid.size(); ++p) {
        for (int c = 0; c < model::kTransportChannels; ++c) {
            for (int t = 0; t < model::kTransportTerms; ++t) {
                EXPECT_EQ(
                    read.transport[p * model::kTransportValues + c * model::kTransportTerms + t],
                    written.transport[p * model::kTransportValues + model::kTransportTerms + t])
                    << "pixel " << p << ", channel " << c << ", term " << t;
            }
        }
    }
}

TEST(ModelFile, StorageIsTheChannelTypeStandardToolsSee) {
    testing::TemporaryFolder folder;
    for (const model::ModelStorage storage :
         {model::ModelStorage::kHalf, model::ModelStorage::kFloat}) {
        model::ModelInfo info = sampleInfo(4, 3, 1);
        info.storage = storage;
        const std::filesystem::path path =
            folder / (std::string(model::storageName(storage)) + ".exr");
        model::ModelRows rows = randomRows(4, 3, 1, 2);
        for (std::vector<float>* values : {&rows.coefficient, &rows.normal, &rows.rms}) {
            for (float& v : *values) {
                v = std::clamp(v, -1.0f, 1.0f);
            }
        }
        writeModel(path, info, rows);
        auto input = OIIO::ImageInput::open(path.string());
        ASSERT_TRUE(input);
        const OIIO::TypeDesc expected =
            storage == model::ModelStorage::kHalf ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT;
        for (int c = 0; c < input->spec().nchannels; ++c) {
            EXPECT_EQ(input->spec().channelformat(c), expected)
                << model::storageName(storage) << " " << input->spec().channelnames[c];
        }
        EXPECT_EQ(model::ModelReader(path).info().storage, storage);
    }
}

TEST(ModelFile, HalfWriterRefusesAValueBeyondTheHalfRangeByPixel) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(5, 4, 1);
    info.storage = model::ModelStorage::kHalf;
    model::ModelRows rows = randomRows(5, 4, 1, 3);
    for (float& v : rows.coefficient) {
        v = std::clamp(v, -1.0f, 1.0f);
    }
    // Pixel (3, 2) of the band written from row 1: image row 3; channel a1.G.
    model::ModelRows band;
    band.resize(5, 3, rows.coefficients);
    band.coefficient[(band.pixel(2, 3) * 3 + 1) * static_cast<std::size_t>(rows.coefficients) + 2] =
        1e5f;
    const std::string message = inputErrorOf([&] {
        model::ModelWriter writer(folder / "model.exr", info);
        writer.writeRows(0, [&] {
            model::ModelRows first;
            first.resize(5, 1, rows.coefficients);
            return first;
        }());
        writer.writeRows(1, band);
        writer.finish();
    });
    EXPECT_NE(message.find("model.exr"), std::string::npos) << message;
    EXPECT_NE(message.find("pixel (3, 3)"), std::string::npos) << message;
    EXPECT_NE(message.find("a1.G"), std::string::npos) << message;
    EXPECT_NE(message.find("--storage float"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_TRUE(std::filesystem::is_empty(folder.path()));
    // In float the same value is kept exactly.
    info.storage = model::ModelStorage::kFloat;
    model::ModelWriter writer(folder / "model.exr", info);
    writer.writeRows(0, band);
    writer.finish();
}

TEST(ModelFile, TheReliefIsOptionalAndRoundTrips) {
    testing::TemporaryFolder folder;
    model::ModelInfo info = sampleInfo(4, 3, 1);
    model::ModelRows rows = randomRows(info.width, info.height, info.harmonics, 5);
    writeModel(folder / "flat.exr", info, rows);  // written without: older files read the same
    model::ModelReader flat(folder / "flat.exr");
    EXPECT_FALSE(flat.info().detailNormals);
    model::ModelRows read;
    flat.readRows(0, info.height, read);
    EXPECT_TRUE(read.detail.empty());

    info.detailNormals = true;
    {
        model::ModelWriter writer(folder / "relief.exr", info);
        rows.resize(info.width, info.height, rows.coefficients, false, true);
        for (std::size_t i = 0; i < rows.detail.size(); ++i) {
            rows.detail[i] = 0.01f * static_cast<float>(i);
        }
        writer.writeRows(0, rows);
        writer.finish();
    }
    model::ModelReader relief(folder / "relief.exr");
    EXPECT_TRUE(relief.info().detailNormals);
    relief.readRows(0, info.height, read);
    EXPECT_TRUE(sameBits(read.detail, rows.detail));
}

TEST(ModelFile, RowsCanBeReadInBands) {
    testing::TemporaryFolder folder;
    const model::ModelInfo info = sampleInfo(5, 6, 1);
    const model::ModelRows written = writeRandomModel(folder / "model.exr", info, 11);
    model::ModelReader reader(folder / "model.exr");
    model::ModelRows band;
    for (int begin = 0; begin < info.height; begin += 4) {
        const int rows = std::min(4, info.height - begin);
        reader.readRows(begin, rows, band);
        for (int r = 0; r < rows; ++r) {
            for (int x = 0; x < info.width; ++x) {
                for (int c = 0; c < 3; ++c) {
                    for (int k = 0; k < band.coefficients; ++k) {
                        ASSERT_EQ(band.coefficientsAt(r, x, c)[k],
                                  written.coefficientsAt(begin + r, x, c)[k]);
                    }
                }
                ASSERT_EQ(band.valid[band.pixel(r, x)], written.valid[written.pixel(begin + r, x)]);
            }
        }
    }
}

TEST(ModelFile, ChannelNamesAreVisibleToStandardExrTools) {
    testing::TemporaryFolder folder;
    const model::ModelInfo info = sampleInfo(3, 2, 2);
    writeRandomModel(folder / "model.exr", info, 5);
    auto input = OIIO::ImageInput::open((folder / "model.exr").string());
    ASSERT_TRUE(input);
    const std::vector<std::string>& names = input->spec().channelnames;
    for (const char* name :
         {"kd.R", "kd.G", "kd.B", "a0.G", "a1.B", "b1.R", "a2.G", "b2.B", "normal.X", "normal.Y",
          "normal.Z", "rms.R", "rms.G", "rms.B", "valid"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    }
    // 6 coefficients × RGB, the normal, the RMS and the flag: nothing else.
    EXPECT_EQ(names.size(), 6u * 3 + 3 + 3 + 1);
    EXPECT_EQ(input->spec().get_string_attribute("vpeFormat"), "vpe-fourier-brdf");
    EXPECT_EQ(input->spec().get_int_attribute("vpeHarmonics"), 2);
}

// Why ModelReader refuses to open `path`; the message must name the file.
std::string readerRefusalOf(const std::filesystem::path& path) {
    const std::string message = inputErrorOf([&] { model::ModelReader reader(path); });
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    return message;
}

TEST(ModelFile, ReaderRefusesAPlainExr) {
    testing::TemporaryFolder folder;
    const std::filesystem::path path = folder / "plain.exr";
    writePlainExr(path, 4, 4);
    const std::string message = readerRefusalOf(path);
    EXPECT_NE(message.find("vpeFormat"), std::string::npos) << message;
}

TEST(ModelFile, ReaderRefusesAnotherFormatVersion) {
    testing::TemporaryFolder folder;
    const std::filesystem::path path = folder / "future.exr";
    writePlainExr(path, 4, 4, [](OIIO::ImageSpec& spec) {
        spec.attribute("vpeFormat", "vpe-fourier-brdf");
        spec.attribute("vpeFormatVersion", 2);
        spec.attribute("vpeHarmonics", 0);
    });
    const std::string message = readerRefusalOf(path);
    EXPECT_NE(message.find("version 2"), std::string::npos) << message;
}

TEST(ModelFile, ReaderRefusesAMissingFile) {
    testing::TemporaryFolder folder;
    readerRefusalOf(folder / "absent.exr");
}

TEST(ModelFile, ReaderRefusesATruncatedFile) {
    testing::TemporaryFolder folder;
    const std::filesystem::path path = folder / "model.exr";
    // Random values do not compress: the cut falls inside the pixel data, past the header.
    const model::ModelInfo info = sampleInfo(64, 64, 3);
    writeRandomModel(path, info, 7);
    std::string bytes;
    {
        std::ifstream stream(path, std::ios::binary);
        std::ostringstream text;
        text << stream.rdbuf();
        bytes = text.str();
    }
    for (const double keep : {0.6, 0.2, 0.01}) {
        SCOPED_TRACE("kept " + std::to_string(keep));
        {
            std::ofstream stream(path, std::ios::binary | std::ios::trunc);
            stream.write(bytes.data(),
                         static_cast<std::streamsize>(static_cast<double>(bytes.size()) * keep));
        }
        const std::string message = inputErrorOf([&] {
            model::ModelReader reader(path);
            model::ModelRows rows;
            reader.readRows(0, reader.info().height, rows);
        });
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    }
}

TEST(ModelFile, WriterRefusesAnotherExtension) {
    testing::TemporaryFolder folder;
    const std::string message =
        inputErrorOf([&] { model::ModelWriter writer(folder / "model.tif", sampleInfo(2, 2, 0)); });
    EXPECT_NE(message.find("model.tif"), std::string::npos) << message;
    EXPECT_TRUE(std::filesystem::is_empty(folder.path()));
}

TEST(ModelFile, WriterWithoutFinishLeavesNoFile) {
    testing::TemporaryFolder folder;
    const model::ModelInfo info = sampleInfo(4, 4, 1);
    { model::ModelWriter writer(folder / "unwritten.exr", info); }
    {
        model::ModelWriter writer(folder / "partial.exr", info);
        writer.writeRows(0, randomRows(info.width, 2, info.harmonics, 1));
    }
    EXPECT_TRUE(std::filesystem::is_empty(folder.path()))
        << std::filesystem::directory_iterator(folder.path())->path();
}

}  // namespace
}  // namespace vpe
