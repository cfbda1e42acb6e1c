// SPDX-License-Identifier: MIT
// The camera's response from an exposure bracket, against a simulated camera whose response is
// known (an ISP's gamma 2.2, 8-bit, RGB, with shot and read noise), photographing a projector's
// ramp on a plaster wall at five exposures; the identity table and its CSV; and the brackets
// the fit refuses, each in one line.
#include "vpe/radiometry/camera_response.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/procam/procam_simulator.h"

#include "support/test_data.h"

namespace vpe::radiometry {
namespace {

namespace procam = renderer::procam;
using testing::TemporaryFolder;

constexpr double kGamma = 2.2;

// A flat wall 1 m in front of the projector, wider than both views, tinted so that the three
// channels see different light; the camera 4 cm beside the projector.
procam::ProcamScene wallScene() {
    procam::ProcamScene scene;
    procam::ScreenObject wall;
    wall.positions = {
        {-0.5f, -0.5f, 1.0f}, {0.5f, -0.5f, 1.0f}, {0.5f, 0.5f, 1.0f}, {-0.5f, 0.5f, 1.0f}};
    wall.normals.assign(4, {0.0f, 0.0f, -1.0f});
    wall.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    wall.indices = {0, 1, 2, 0, 2, 3};
    scene.object = wall;
    scene.albedo.base = {0.85, 0.6, 0.35};
    scene.projector.camera = proto::cameraLookingAt(64, 48, 20, {0, 0, 0}, {0, 0, 1});
    scene.room.interreflection = false;  // a plane sees nothing of itself
    return scene;
}

procam::SimulatedCamera gammaCamera(double exposure) {
    procam::SimulatedCamera camera;
    camera.camera = proto::cameraLookingAt(160, 120, 14, {-0.04, 0, 0}, {0, 0, 1});
    camera.response = procam::CameraResponse::kGamma;
    camera.gamma = kGamma;
    camera.bits = 8;
    camera.monochrome = false;
    camera.exposure = exposure;
    return camera;
}

BracketedImage bracketed(const procam::CameraFrame& frame, double exposure) {
    BracketedImage image;
    image.width = frame.width;
    image.height = frame.height;
    image.channels = frame.channels;
    image.maxValue = frame.maxValue();
    image.samples = frame.samples;
    image.exposure = exposure;
    return image;
}

// The projector shows a horizontal ramp (all channels at x / (width − 1), as the radiometric
// capture's ramp) photographed at 5 exposures a stop apart, the longest clipping the brightest
// third of the wall: codes from the read noise up to saturation. The exposure belongs to the
// simulator's camera, so each exposure has a simulator of its own on the same scene (a small
// one: tracing it is cheap); the radiance is the first one's.
const std::vector<BracketedImage>& bracket() {
    static const std::vector<BracketedImage> images = [] {
        const procam::ProcamScene scene = wallScene();
        renderer::RgbImage ramp(64, 48);
        for (int y = 0; y < 48; ++y) {
            for (int x = 0; x < 64; ++x) {
                std::fill_n(ramp.pixel(x, y), 3, static_cast<float>(x) / 63.0f);
            }
        }
        std::vector<BracketedImage> result;
        renderer::RgbImage radiance;
        for (int stop = 0; stop < 5; ++stop) {
            const double exposure = 8.0 / (1 << stop);
            const procam::ProcamSimulator simulator(scene, gammaCamera(exposure), 2);
            if (stop == 0) {
                radiance = simulator.radiance(ramp);
            }
            // Exposures in microseconds, as a camera reports them: only their ratios count.
            result.push_back(bracketed(simulator.expose(radiance, static_cast<std::uint64_t>(stop)),
                                       exposure * 1000));
        }
        return result;
    }();
    return images;
}

// The message of the InputError `f` throws; fails the test when it throws none.
template <typename F>
std::string errorOf(F f) {
    try {
        f();
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
        return message;
    }
    ADD_FAILURE() << "no InputError thrown";
    return {};
}

#define EXPECT_INPUT_ERROR(statement, fragment)                            \
    do {                                                                   \
        const std::string message_ = errorOf([&] { (void)(statement); });  \
        EXPECT_NE(message_.find(fragment), std::string::npos) << message_; \
    } while (false)

// Relative error of a fitted table against (code / 255)^γ, per channel, over codes [from, 240].
struct Accuracy {
    double worst = 0, rms = 0;
};

Accuracy accuracy(const CameraLinearization& fitted, int from) {
    Accuracy result;
    int count = 0;
    for (int c = 0; c < fitted.channels(); ++c) {
        for (int code = from; code <= 240; ++code) {
            const double relative = fitted.linear(c, code) / std::pow(code / 255.0, kGamma) - 1;
            result.worst = std::max(result.worst, std::abs(relative));
            result.rms += relative * relative;
            ++count;
        }
    }
    result.rms = std::sqrt(result.rms / count);
    return result;
}

// The most a fit may be off the truth, relatively: worst and RMS over codes 16..240, worst
// over 32..240.
struct AccuracyLimits {
    double wideWorst, wideRms, brightWorst;
};

// Prints how far `fitted` is off the truth, as `what`, and holds it to `limits`.
void expectAccurate(const CameraLinearization& fitted, const char* what,
                    const AccuracyLimits& limits) {
    const Accuracy wide = accuracy(fitted, 16), bright = accuracy(fitted, 32);
    std::printf("%s, codes 16..240: max relative error %.4f, RMS %.4f; codes 32..240: max %.4f\n",
                what, wide.worst, wide.rms, bright.worst);
    EXPECT_LT(wide.worst, limits.wideWorst);
    EXPECT_LT(wide.rms, limits.wideRms);
    EXPECT_LT(bright.worst, limits.brightWorst);
}

void expectWellFormed(const CameraLinearization& fitted) {
    ASSERT_EQ(fitted.maxValue(), 255);
    EXPECT_FALSE(fitted.isLinear());
    for (int c = 0; c < fitted.channels(); ++c) {
        EXPECT_EQ(fitted.linear(c, 255), 1.0);
        EXPECT_GE(fitted.linear(c, 0), 0.0);
        for (int code = 1; code <= 255; ++code) {
            EXPECT_GE(fitted.linear(c, code), fitted.linear(c, code - 1)) << c << " " << code;
        }
    }
}

TEST(CameraResponse, RecoversAGammaCameraFromABracket) {
    const std::vector<BracketedImage>& images = bracket();
    const auto start = std::chrono::steady_clock::now();
    const CameraLinearization fitted = fitCameraResponse(images);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("camera response: fit %.2f s\n", seconds);
    ASSERT_EQ(fitted.channels(), 3);
    expectWellFormed(fitted);
    // Each channel is its own scale, 1 at its top code: the truth is (code / 255)^γ in all
    // three, though the wall sends them different light (blue never gets above code 201, so
    // its top is extrapolated; red clips in the longest exposure).
    // Measured: 0.292 and 0.0238 over 16..240, 0.0425 over 32..240. The worst codes are the
    // darkest: code 16 is 14 electrons against 4 of read noise, and the noise, clipped at 0
    // and compressed by the gamma, biases them up; from code 32 on the error is a few percent.
    expectAccurate(fitted, "camera response", {0.45, 0.036, 0.065});
}

TEST(CameraResponse, FitsAMonochromeBracketAsOneChannel) {
    // The green channel alone, as a monochrome camera would record the same wall.
    std::vector<BracketedImage> images;
    for (const BracketedImage& colour : bracket()) {
        BracketedImage grey = colour;
        grey.channels = 1;
        grey.samples.clear();
        for (std::size_t i = 1; i < colour.samples.size(); i += 3) {
            grey.samples.push_back(colour.samples[i]);
        }
        images.push_back(std::move(grey));
    }
    const CameraLinearization fitted = fitCameraResponse(images);
    ASSERT_EQ(fitted.channels(), 1);
    expectWellFormed(fitted);
    // Measured: 0.250 and 0.0298 over 16..240, 0.0333 over 32..240.
    expectAccurate(fitted, "monochrome camera response", {0.375, 0.045, 0.05});
}

TEST(CameraResponse, TheTableRoundTripsThroughCsv) {
    const TemporaryFolder folder;
    const CameraLinearization identity = CameraLinearization::identity(255, 3);
    EXPECT_TRUE(identity.isLinear());
    EXPECT_EQ(identity.channels(), 3);
    EXPECT_EQ(identity.linear(2, 51), 0.2);
    EXPECT_EQ(identity.linear(0, 0), 0.0);
    EXPECT_EQ(identity.linear(1, 255), 1.0);
    writeCameraResponseCsv(folder / "identity.csv", identity);
    const CameraLinearization read = readCameraResponseCsv(folder / "identity.csv");
    EXPECT_TRUE(read.isLinear());
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(read.table(c), identity.table(c));
    }
    std::ifstream csv(folder / "identity.csv");
    std::string header, first;
    std::getline(csv, header);
    std::getline(csv, first);
    EXPECT_EQ(header, "code,r,g,b");
    EXPECT_EQ(first, "0,0,0,0");

    // A 10-bit monochrome identity, and a fitted table: every digit survives.
    const CameraLinearization tenBit = CameraLinearization::identity(1023, 1);
    writeCameraResponseCsv(folder / "ten-bit.csv", tenBit);
    const CameraLinearization tenBitRead = readCameraResponseCsv(folder / "ten-bit.csv");
    EXPECT_EQ(tenBitRead.maxValue(), 1023);
    EXPECT_EQ(tenBitRead.channels(), 1);
    EXPECT_TRUE(tenBitRead.isLinear());
    std::vector<double> curve(256);
    for (int code = 0; code <= 255; ++code) {
        curve[static_cast<std::size_t>(code)] = std::pow(code / 255.0, kGamma);
    }
    const CameraLinearization gamma = CameraLinearization::fromTables({curve, curve, curve});
    EXPECT_FALSE(gamma.isLinear());
    writeCameraResponseCsv(folder / "gamma.csv", gamma);
    const CameraLinearization gammaRead = readCameraResponseCsv(folder / "gamma.csv");
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(gammaRead.table(c), curve);
    }
}

TEST(CameraResponse, RefusesBadTablesAndFiles) {
    const TemporaryFolder folder;
    std::vector<double> curve{0, 0.5, 0.4, 1};
    EXPECT_INPUT_ERROR(CameraLinearization::fromTables({curve}),
                       "camera response: value, code 2: 0.4 is below the previous 0.5");
    curve = {0, 0.5, 1};
    EXPECT_INPUT_ERROR(CameraLinearization::fromTables({curve, curve, {0, 0.5, 0.8}}),
                       "camera response: b: the top code is 0.8; it must be 1");
    EXPECT_INPUT_ERROR(CameraLinearization::fromTables({{0, 1}, {0, 1}}), "2 channels");
    EXPECT_INPUT_ERROR(CameraLinearization::fromTables({{0, std::nan(""), 1}}),
                       "code 1: nan is not a finite number");

    std::ofstream(folder / "gap.csv") << "code,value\n0,0\n1,0.5\n3,1\n";
    EXPECT_INPUT_ERROR(readCameraResponseCsv(folder / "gap.csv"),
                       "gap.csv:4: code '3' where 2 comes next");
    std::ofstream(folder / "falls.csv") << "# a comment\ncode,value\n0,0\n1,0.6\n2,0.5\n3,1\n";
    EXPECT_INPUT_ERROR(readCameraResponseCsv(folder / "falls.csv"),
                       "falls.csv: value, code 2: 0.5 is below the previous 0.6");
    std::ofstream(folder / "fields.csv") << "0,0,0,0\n1,1,1\n";
    EXPECT_INPUT_ERROR(readCameraResponseCsv(folder / "fields.csv"),
                       "fields.csv:2: expected 4 fields");
    EXPECT_INPUT_ERROR(readCameraResponseCsv(folder / "missing.csv"),
                       "missing.csv: cannot open camera response");
}

// A bracket of small images whose content does not matter: the checks come before the fit.
std::vector<BracketedImage> smallBracket(int count) {
    std::vector<BracketedImage> images;
    for (int i = 0; i < count; ++i) {
        BracketedImage image;
        image.width = 16;
        image.height = 8;
        image.channels = 3;
        image.samples.assign(16 * 8 * 3, 100);
        image.exposure = 1000.0 * (i + 1);
        images.push_back(image);
    }
    return images;
}

TEST(CameraResponse, RefusesBadBrackets) {
    EXPECT_INPUT_ERROR(fitCameraResponse(smallBracket(2)),
                       "bracket: 2 images; at least 3 exposures are needed");

    std::vector<BracketedImage> images = smallBracket(3);
    images[2].width = 8;
    images[2].height = 4;
    images[2].samples.resize(8 * 4 * 3);
    EXPECT_INPUT_ERROR(fitCameraResponse(images), "bracket: image 3 is 8x4, the others 16x8");
    // Against the image most share, and named when the others disagree among themselves too.
    images = smallBracket(4);
    images[0].width = images[1].width = 8;
    images[0].samples.resize(8 * 8 * 3);
    images[1].samples.resize(8 * 8 * 3);
    images[2].width = 4;
    images[2].samples.resize(4 * 8 * 3);
    EXPECT_INPUT_ERROR(fitCameraResponse(images), "bracket: image 3 is 4x8, image 1 is 8x8");

    images = smallBracket(4);
    images[3].exposure = images[1].exposure;
    EXPECT_INPUT_ERROR(
        fitCameraResponse(images),
        "bracket: images 2 and 4 have the same exposure 2000; exposures must differ");

    images = smallBracket(3);
    for (BracketedImage& image : images) {
        image.maxValue = 1023;
    }
    EXPECT_INPUT_ERROR(fitCameraResponse(images),
                       "bracket: image 1 is 10-bit (maxValue 1023); only 8-bit images");

    images = smallBracket(3);
    images[1].channels = 1;
    images[1].samples.resize(16 * 8);
    EXPECT_INPUT_ERROR(fitCameraResponse(images), "bracket: image 2 has 1 channel, the others 3");

    images = smallBracket(3);
    images[2].samples[7] = 300;
    EXPECT_INPUT_ERROR(fitCameraResponse(images), "bracket: image 3, pixel (2, 0): 300 is above");

    // Shades, but over too few codes for a curve.
    images = smallBracket(3);
    for (std::size_t i = 0; i < images.size(); ++i) {
        for (std::size_t s = 0; s < images[i].samples.size(); ++s) {
            images[i].samples[s] = static_cast<std::uint16_t>(100 + s / 24 + 5 * i);
        }
    }
    EXPECT_INPUT_ERROR(fitCameraResponse(images),
                       "bracket: channel r shows codes 100..125 only below the clip");
    // A flat grey wall tells nothing about the response.
    EXPECT_INPUT_ERROR(fitCameraResponse(smallBracket(3)),
                       "bracket: only 1 pixel of distinct brightness");
}

}  // namespace
}  // namespace vpe::radiometry
