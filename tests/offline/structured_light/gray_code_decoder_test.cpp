// SPDX-License-Identifier: MIT
// Decoding a Gray code without phase images: whole bins where the camera is clean or noisy, with
// white and black or without them, with a code step; an edge inside a pixel placed on the edge,
// not dropped; a frame captured wrong, or codes beyond the declared projector, refused in one
// line naming the file.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/structured_light/pattern_decoder.h"
#include "vpe/structured_light/scan_capture.h"

#include "support/shared_test_folders.h"
#include "synthetic_gray_code.h"

namespace vpe::testing {
namespace {

namespace fs = std::filesystem;

// The decoded coordinates against what each pixel sees: the largest error and how many pixels
// are off by more than `tolerance` (projector pixels, either axis).
struct DecodeErrors {
    double worst = 0;
    std::size_t beyond = 0;
};

DecodeErrors compare(const structured_light::DecodedScan& decoded, const SyntheticGrayCode& truth,
                     double binWidth, double tolerance) {
    DecodeErrors errors;
    for (int v = 0; v < decoded.height; ++v) {
        for (int u = 0; u < decoded.width; ++u) {
            const std::size_t p = static_cast<std::size_t>(v) * decoded.width + u;
            if (std::isnan(decoded.projectorX[p])) {
                continue;
            }
            // The centre of the bin the seen point falls in.
            const auto centre = [&](double c) {
                const double column = std::floor(c + 0.5);
                return std::floor(column / binWidth) * binWidth + (binWidth - 1) / 2;
            };
            const double error =
                std::max(std::abs(decoded.projectorX[p] - centre(truth.projectorX(u))),
                         std::abs(decoded.projectorY[p] - centre(truth.projectorY(v))));
            errors.worst = std::max(errors.worst, error);
            errors.beyond += error > tolerance ? 1 : 0;
        }
    }
    return errors;
}

structured_light::DecodedScan decodeSynthetic(const SyntheticGrayCode& capture,
                                              const std::string& name) {
    const fs::path folder = scratchFolder("vpe-gray-code-" + name);
    writeSyntheticScan(capture, folder);
    const structured_light::ScanCapture scan(folder);
    structured_light::DecodedScan decoded = structured_light::decodePatterns(scan);
    fs::remove_all(folder);
    return decoded;
}

TEST(GrayCodeDecoder, GivesWholeBinsWithWhiteAndBlackShownLast) {
    const SyntheticGrayCode capture;
    const structured_light::DecodedScan decoded = decodeSynthetic(capture, "flats");
    EXPECT_EQ(decoded.lit, 160u * 120u);
    EXPECT_EQ(decoded.decoded, decoded.lit);
    const DecodeErrors errors = compare(decoded, capture, 1, 0);
    EXPECT_EQ(errors.beyond, 0u) << "worst " << errors.worst;
    EXPECT_FLOAT_EQ(decoded.precision[0], static_cast<float>(1 / std::sqrt(12.0)));
    // The noise measured on the capture: 0.004 drawn, 0.0042 with the 8-bit rounding, which the
    // median absolute deviation of whole levels reads about 30 % low (measured 0.0029).
    EXPECT_GT(decoded.noise.sigma(0.3), 0.0042 / 1.5);
    EXPECT_LT(decoded.noise.sigma(0.3), 0.0042 * 1.5);
}

TEST(GrayCodeDecoder, WithoutWhiteAndBlackThePairsStandIn) {
    SyntheticGrayCode capture;
    capture.patterns.flatFields = false;
    const structured_light::DecodedScan decoded = decodeSynthetic(capture, "no-flats");
    EXPECT_EQ(decoded.lit, 160u * 120u);
    EXPECT_EQ(decoded.decoded, decoded.lit);
    EXPECT_EQ(compare(decoded, capture, 1, 0).beyond, 0u);
    EXPECT_NEAR(decoded.white[500], capture.black + capture.albedo, 0.02);
    EXPECT_NEAR(decoded.black[500], capture.black, 0.02);
    EXPECT_GT(decoded.noise.sigma(0.3), 0.0042 / 1.5);
    EXPECT_LT(decoded.noise.sigma(0.3), 0.0042 * 1.5);
}

// A dim target on a noisy camera: the pairs differ by 0.1 (25 levels) against a noise of 0.006
// on each frame, 0.0087 on their difference with the rounding: eleven standard deviations, so
// every code is certain and every pixel must be kept.
TEST(GrayCodeDecoder, ANoisyCameraKeepsEveryCertainCode) {
    SyntheticGrayCode capture;
    capture.albedo = 0.1;
    capture.noise = 0.006;
    const structured_light::DecodedScan decoded = decodeSynthetic(capture, "noisy");
    EXPECT_EQ(decoded.lit, 160u * 120u);
    EXPECT_EQ(decoded.decoded, decoded.lit);
    EXPECT_EQ(compare(decoded, capture, 1, 0).beyond, 0u);
}

TEST(GrayCodeDecoder, ACodeStepGivesBinsOfItsWidth) {
    SyntheticGrayCode capture;
    capture.patterns.codeStep = 2;
    capture.patterns.lowestGrayBit = 1;
    const structured_light::DecodedScan decoded = decodeSynthetic(capture, "step");
    EXPECT_EQ(decoded.decoded, 160u * 120u);
    EXPECT_EQ(compare(decoded, capture, 4, 0).beyond, 0u);
    EXPECT_FLOAT_EQ(decoded.precision[0], static_cast<float>(4 / std::sqrt(12.0)));
}

// Each camera pixel spans a projector pixel: most straddle a stripe's edge. The bit that differs
// there is decided by the larger share or, at an even split, left open and the pixel placed on
// the edge: within half a pixel of what it sees either way, and none dropped.
TEST(GrayCodeDecoder, APixelAcrossAStripeEdgeIsKeptBesideIt) {
    SyntheticGrayCode capture;
    capture.footprint = 1.0;
    const structured_light::DecodedScan decoded = decodeSynthetic(capture, "edges");
    EXPECT_EQ(decoded.decoded, 160u * 120u);
    double worst = 0;
    for (int v = 0; v < decoded.height; ++v) {
        for (int u = 0; u < decoded.width; ++u) {
            const std::size_t p = static_cast<std::size_t>(v) * decoded.width + u;
            worst = std::max({worst, std::abs(decoded.projectorX[p] - capture.projectorX(u)),
                              std::abs(decoded.projectorY[p] - capture.projectorY(v))});
        }
    }
    // Half a pixel, and what the noise adds at a split close to even.
    EXPECT_LE(worst, 0.55);
}

TEST(GrayCodeDecoder, RefusesAFrameCapturedBlackNamingIt) {
    const fs::path folder = scratchFolder("vpe-gray-code-black");
    const SyntheticGrayCode capture;
    writeSyntheticScan(capture, folder);
    // The fourth image: gray-x-b4-inv (the tool's order: x bit 5, its inverse, bit 4, …).
    const std::string file = proto::scanImageName(3, toolOrder(capture.patterns)[3]);
    const std::vector<std::uint8_t> black(160 * 120, 12);
    proto::writePnmAtomically(folder / file, 160, 120, 1, black);
    const structured_light::ScanCapture scan(folder);
    try {
        structured_light::decodePatterns(scan);
        ADD_FAILURE() << "decoded a capture with a black frame";
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find(file), std::string::npos) << message;
        EXPECT_NE(message.find("black or stale"), std::string::npos) << message;
    }
    fs::remove_all(folder);
}

// Patterns made for a 64 × 48 projector in a manifest that declares 48 × 48: the same 26 images
// (6 bits per axis), so only the codes can tell. The camera sees columns 0.3 .. 59.2: a fifth
// of its codes are 48..59, which a 48-column projector does not have.
TEST(GrayCodeDecoder, RefusesCodesBeyondTheDeclaredProjectorNamingTheManifest) {
    const fs::path folder = scratchFolder("vpe-gray-code-wrong-size");
    const SyntheticGrayCode capture;
    writeSyntheticScan(capture, folder);
    proto::ScanManifest manifest = proto::readScanManifest(folder);
    manifest.patterns.width = 48;
    proto::writeScanManifest(folder, manifest);
    const structured_light::ScanCapture scan(folder);
    try {
        structured_light::decodePatterns(scan);
        ADD_FAILURE() << "decoded codes a 48x48 projector does not have";
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        for (const char* mention :
             {"scan.json: 20% of the decoded column codes are 48..59, beyond the 48 column codes "
              "(0..47) a 48x48 projector with step 1 has: is the projector's size right"}) {
            EXPECT_NE(message.find(mention), std::string::npos) << message;
        }
        EXPECT_EQ(message.find("row"), std::string::npos) << message;
    }
    // Declared right, the same images decode whole (GivesWholeBinsWithWhiteAndBlackShownLast).
    manifest.patterns.width = 64;
    proto::writeScanManifest(folder, manifest);
    EXPECT_EQ(structured_light::decodePatterns(structured_light::ScanCapture(folder)).decoded,
              160u * 120u);
    fs::remove_all(folder);
}

}  // namespace
}  // namespace vpe::testing
