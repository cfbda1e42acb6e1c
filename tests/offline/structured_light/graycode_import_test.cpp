// SPDX-License-Identifier: MIT
// vpe import-graycode as a user runs it on procam-calibration's captures: the scan folders it
// writes decode to what the camera saw, and every bad capture is refused in one line naming the
// file, with exit status 2 and no output folder.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/proto/scan_manifest.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/structured_light/pattern_decoder.h"
#include "vpe/structured_light/scan_capture.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/shared_test_folders.h"
#include "synthetic_gray_code.h"

namespace vpe::testing {
namespace {

namespace fs = std::filesystem;

// Two poses of a 64 × 48 projector: 2·(6 + 6) + 2 = 26 images each.
fs::path twoCaptures(const std::string& name) {
    const fs::path folder = scratchFolder("vpe-import-graycode-" + name);
    SyntheticGrayCode capture;
    writeToolCapture(capture, folder / "capture_0");
    capture.offset = 2.1;
    capture.seed = 2;
    writeToolCapture(capture, folder / "capture_1");
    return folder;
}

std::vector<std::string> importCommand(const fs::path& folder,
                                       const std::string& projector = "64x48") {
    return vpeCommand({"import-graycode", (folder / "capture_0").string(),
                       (folder / "capture_1").string(), "--projector", projector, "--out",
                       (folder / "scans").string()});
}

TEST(ImportGrayCode, WritesScanFoldersThatDecodeToWhatTheCameraSaw) {
    const fs::path folder = twoCaptures("good");
    std::vector<std::string> command = importCommand(folder);
    command.push_back("--json");
    const CommandResult result = runCommand(command);
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJsonLine(result.out);
    ASSERT_EQ(report["scans"].size(), 2u);
    EXPECT_EQ(report["scans"][0]["images"], 26);

    const structured_light::ScanCapture scan(folder / "scans" / "capture_1");
    const proto::ScanManifest& manifest = scan.manifest();
    EXPECT_EQ(manifest.patterns.phaseSteps, 0);
    EXPECT_EQ(manifest.camera.width, 160);
    EXPECT_EQ(manifest.images.front().file, "graycode_00.png");
    EXPECT_EQ(manifest.images.front().pattern, "gray-x-b5");
    EXPECT_EQ(manifest.images[1].pattern, "gray-x-b5-inv");
    EXPECT_EQ(manifest.images[12].pattern, "gray-y-b5");
    EXPECT_EQ(manifest.images[24].pattern, "white");
    EXPECT_EQ(manifest.images[25].pattern, "black");
    const structured_light::DecodedScan decoded = structured_light::decodePatterns(scan);
    EXPECT_EQ(decoded.decoded, 160u * 120u);
    // The second pose sees projector point 2.1 + 0.37·u (a point sample: its column exactly).
    for (int u = 0; u < 160; u += 7) {
        EXPECT_EQ(decoded.projectorX[static_cast<std::size_t>(u)], std::floor(2.1 + 0.37 * u + 0.5))
            << u;
    }
    fs::remove_all(folder);
}

TEST(ImportGrayCode, RefusesABadCaptureInOneLineAndWritesNothing) {
    {  // a missing image
        const fs::path folder = twoCaptures("missing");
        fs::remove(folder / "capture_1" / "graycode_05.png");
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_1/graycode_05.png", "missing", "gray-x-b3-inv",
                          "holds 25 graycode images", "shows 26 images (2·(6 + 6) + 2)"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // an extra one
        const fs::path folder = twoCaptures("extra");
        fs::copy_file(folder / "capture_0" / "graycode_00.png",
                      folder / "capture_0" / "graycode_26.png");
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_0/graycode_26.png", "an extra image", "holds 27"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // the wrong projector: a count that does not fit
        const fs::path folder = twoCaptures("count");
        expectInputError(runCommand(importCommand(folder, "128x48")),
                         {"capture_0/graycode_26.png", "missing",
                          "128x48 projector with step 1 shows 28 images (2·(7 + 6) + 2)"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // an image that is not one
        const fs::path folder = twoCaptures("unreadable");
        std::ofstream(folder / "capture_1" / "graycode_03.png") << "not a picture";
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_1/graycode_03.png", "cannot read image"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // an image of another size
        const fs::path folder = twoCaptures("size");
        image::writeImage8(folder / "capture_0" / "graycode_07.png", 80, 60, 1,
                           std::vector<std::uint8_t>(80 * 60, 100));
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_0/graycode_07.png", "80x60", "graycode_00.png is 160x120"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // a size and step that make no sequence
        const fs::path folder = twoCaptures("step");
        std::vector<std::string> command = importCommand(folder);
        command.insert(command.end(), {"--step", "40"});
        expectInputError(runCommand(command), {"--projector 64x48 --step 40", "code step 40"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
}

// Pixels decoded in both scans whose coordinates differ (either axis), and those decoded in one
// only.
struct DecodeDifference {
    std::size_t differing = 0, onlyOne = 0, both = 0;
};

DecodeDifference differenceOf(const structured_light::DecodedScan& a,
                              const structured_light::DecodedScan& b) {
    DecodeDifference d;
    for (std::size_t p = 0; p < a.projectorX.size(); ++p) {
        const bool inA = !std::isnan(a.projectorX[p]), inB = !std::isnan(b.projectorX[p]);
        if (inA != inB) {
            ++d.onlyOne;
        } else if (inA) {
            ++d.both;
            d.differing +=
                a.projectorX[p] != b.projectorX[p] || a.projectorY[p] != b.projectorY[p] ? 1 : 0;
        }
    }
    return d;
}

// The same capture as 16-bit TIFF and as JPEG: imported with its own extension and depth, and
// decoded as the PNGs are (the TIFF exactly, the JPEG's artefacts moving a few codes).
TEST(ImportGrayCode, ReadsSixteenBitTiffAndJpegAsThePngs) {
    const fs::path folder = twoCaptures("formats");
    convertToolCapture(folder / "capture_0", folder / "tiff" / "capture_0", ".tif", 16);
    convertToolCapture(folder / "capture_0", folder / "jpeg" / "capture_0", ".jpg", 8, 90);
    const auto importAndDecode = [&](const fs::path& capture, const std::string& format) {
        const fs::path scans = folder / ("scans-" + format);
        const CommandResult result =
            runCommand(vpeCommand({"import-graycode", capture.string(), "--projector", "64x48",
                                   "--out", scans.string()}));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        return structured_light::ScanCapture(scans / "capture_0");
    };
    const structured_light::ScanCapture png = importAndDecode(folder / "capture_0", "png");
    const structured_light::ScanCapture tiff =
        importAndDecode(folder / "tiff" / "capture_0", "tiff");
    const structured_light::ScanCapture jpeg =
        importAndDecode(folder / "jpeg" / "capture_0", "jpeg");
    EXPECT_EQ(tiff.manifest().camera.bits, 16);
    EXPECT_EQ(tiff.manifest().images[3].file, "graycode_03.tif");
    EXPECT_EQ(jpeg.manifest().camera.bits, 8);
    EXPECT_EQ(jpeg.manifest().images[3].file, "graycode_03.jpg");
    const structured_light::DecodedScan fromPng = structured_light::decodePatterns(png);
    const structured_light::DecodedScan fromTiff = structured_light::decodePatterns(tiff);
    const structured_light::DecodedScan fromJpeg = structured_light::decodePatterns(jpeg);
    const DecodeDifference tiffDifference = differenceOf(fromPng, fromTiff);
    const DecodeDifference jpegDifference = differenceOf(fromPng, fromJpeg);
    std::printf(
        "16-bit TIFF: %zu decoded (PNG %zu), %zu differ; JPEG: %zu decoded, %zu of %zu "
        "differ, %zu in one only\n",
        fromTiff.decoded, fromPng.decoded, tiffDifference.differing, fromJpeg.decoded,
        jpegDifference.differing, jpegDifference.both, jpegDifference.onlyOne);
    EXPECT_EQ(fromTiff.decoded, fromPng.decoded);
    EXPECT_EQ(tiffDifference.differing + tiffDifference.onlyOne, 0u);
    EXPECT_NEAR(double(fromJpeg.decoded), double(fromPng.decoded), 0.01 * fromPng.decoded);
    EXPECT_LT(jpegDifference.differing, 0.01 * jpegDifference.both);
    fs::remove_all(folder);
}

TEST(ImportGrayCode, RefusesMixedFormatsAndDepthsNamingTheFiles) {
    {  // one JPEG among PNGs
        const fs::path folder = twoCaptures("mixed");
        convertToolCapture(folder / "capture_1", folder / "jpeg", ".jpg", 8);
        fs::remove(folder / "capture_1" / "graycode_07.png");
        fs::copy_file(folder / "jpeg" / "graycode_07.jpg",
                      folder / "capture_1" / "graycode_07.jpg");
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_1: mixes image formats (graycode_00.png, graycode_07.jpg)"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // a format vpe does not import
        const fs::path folder = twoCaptures("bmp");
        fs::rename(folder / "capture_0" / "graycode_04.png",
                   folder / "capture_0" / "graycode_04.bmp");
        expectInputError(runCommand(importCommand(folder)),
                         {"capture_0/graycode_04.bmp", "not an image format vpe imports"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // a 16-bit TIFF among 8-bit ones
        const fs::path folder = twoCaptures("depth");
        for (const char* capture : {"capture_0", "capture_1"}) {
            convertToolCapture(folder / capture, folder / "tiff" / capture, ".tif", 8);
        }
        convertToolCapture(folder / "capture_1", folder / "deep", ".tif", 16);
        fs::copy_file(folder / "deep" / "graycode_09.tif",
                      folder / "tiff" / "capture_1" / "graycode_09.tif",
                      fs::copy_options::overwrite_existing);
        const CommandResult result =
            runCommand(vpeCommand({"import-graycode", (folder / "tiff" / "capture_0").string(),
                                   (folder / "tiff" / "capture_1").string(), "--projector", "64x48",
                                   "--out", (folder / "scans").string()}));
        expectInputError(result,
                         {"capture_1/graycode_09.tif: 16-bit, but graycode_00.tif is 8-bit"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
    {  // float samples
        const fs::path folder = twoCaptures("float");
        convertToolCapture(folder / "capture_0", folder / "tiff" / "capture_0", ".tif", 8);
        image::writeImage(folder / "tiff" / "capture_0" / "graycode_02.tif", 160, 120, 1,
                          std::vector<float>(160 * 120, 0.5f), image::PixelFormat::kFloat);
        const CommandResult result =
            runCommand(vpeCommand({"import-graycode", (folder / "tiff" / "capture_0").string(),
                                   "--projector", "64x48", "--out", (folder / "scans").string()}));
        expectInputError(result, {"capture_0/graycode_02.tif: 32-bit float samples"});
        EXPECT_FALSE(fs::exists(folder / "scans"));
        fs::remove_all(folder);
    }
}

// The wrong projector with the right image count: 64 × 48 patterns imported as 48 × 48 (26
// images either way) import, and the first decode refuses them in one line naming the
// capture's manifest, writing nothing.
TEST(ImportGrayCode, AWrongProjectorSizeIsRefusedAtDecode) {
    const fs::path folder = twoCaptures("wrong-size");
    const CommandResult imported = runCommand(importCommand(folder, "48x48"));
    ASSERT_EQ(imported.exitStatus, 0) << imported.err;
    proto::PinholeCamera camera;
    camera.width = 160;
    camera.height = 120;
    camera.K = {200, 0, 79.5, 0, 200, 59.5, 0, 0, 1};
    scene::ProjectorCalibration projector = camera;
    projector.width = 48;
    projector.height = 48;
    projector.T = {-0.1, 0, 0};
    scene::writeProcamCalibration(projector, camera, std::nullopt, folder / "procam.yml");
    expectInputError(
        runCommand(
            vpeCommand({"scan", (folder / "scans" / "capture_0").string(), "--calibration",
                        (folder / "procam.yml").string(), "--out", (folder / "scan").string()})),
        {"capture_0/scan.json: 20% of the decoded column codes are 48..", "a 48x48 projector",
         "is the projector's size right (vpe import-graycode --projector, --step)?"});
    EXPECT_FALSE(fs::exists(folder / "scan"));
    fs::remove_all(folder);
}

}  // namespace
}  // namespace vpe::testing
