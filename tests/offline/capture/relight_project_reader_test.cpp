// SPDX-License-Identifier: MIT
// RelightLab projects (.relight) as captures: a small project in the layout RelightLab saves
// (QJsonDocument: keys sorted, four-space indent), and malformed ones.
#include "vpe/capture/relight_project_reader.h"

#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"

#include "support/test_data.h"

namespace vpe {
namespace {

const std::filesystem::path kSource = "/captures/door/door.relight";

// Four images; the third is skipped (no direction), the fourth hidden (a direction, unused).
const char* const kProject = R"({
    "application": "RelightLab",
    "created": "2025-03-14T10:21:07",
    "dome": {
        "directions": [
            { "x": 0.5, "y": 0.0, "z": 0.8660254 },
            { "x": 0.0, "y": -1.0, "z": 1.0 },
            { "x": -0.25, "y": 0.25, "z": 0.9354143 }
        ],
        "domeDiameter": 500,
        "imageWidth": 60,
        "label": "test dome",
        "ledAdjust": [],
        "lightConfiguration": "directional",
        "notes": "",
        "positions3d": [],
        "positionsSphere": [],
        "verticalOffset": 0
    },
    "folder": "photos",
    "height": 439,
    "images": [
        { "filename": "IMG_0001.JPG", "skip": false, "visible": true },
        { "filename": "IMG 0002.JPG", "skip": false, "visible": true },
        { "filename": "IMG_0003.JPG", "skip": true, "visible": true },
        { "filename": "IMG_0004.JPG", "skip": false, "visible": false }
    ],
    "lens": { "focal35equivalent": true, "focalLength": 0, "pixelSizeX": 0, "pixelSizeY": 0 },
    "version": "2024.11",
    "width": 487
})";

std::string rejectionOf(const std::string& text) {
    try {
        capture::parseRelightProject(text, kSource);
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.rfind(kSource.string() + ": ", 0), 0u) << message;
        return message;
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
}

std::string edited(const std::string& from, const std::string& to) {
    std::string text = kProject;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}

TEST(RelightProjectReader, ReadsImagesAndDirectionsOfTheVisibleImages) {
    const capture::Capture capture = capture::parseRelightProject(kProject, kSource);
    EXPECT_EQ(capture.lightKind, capture::LightKind::kDirectional);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].file, std::filesystem::path("/captures/door/photos/IMG_0001.JPG"));
    EXPECT_EQ(capture.images[1].file, std::filesystem::path("/captures/door/photos/IMG 0002.JPG"));
    EXPECT_NEAR(capture.images[0].light.x, 0.5, 1e-7);
    EXPECT_NEAR(capture.images[0].light.z, 0.8660254, 1e-7);
    // Normalized on read, as .lp directions are.
    EXPECT_NEAR(capture.images[1].light.y, -std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(capture.images[1].light.z, std::sqrt(0.5), 1e-12);
}

TEST(RelightProjectReader, OpenCaptureTakesAProjectFile) {
    testing::TemporaryFolder folder;
    std::ofstream(folder / "scan.relight") << kProject;
    const capture::Capture capture = capture::openCapture(folder / "scan.relight");
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].file, folder / "photos" / "IMG_0001.JPG");
}

TEST(RelightProjectReader, RefusesMalformedProjects) {
    EXPECT_NE(rejectionOf("{\"images\": [").find("malformed JSON"), std::string::npos);
    EXPECT_NE(rejectionOf("[1, 2]").find("not a JSON object"), std::string::npos);
    EXPECT_NE(rejectionOf(edited("\"images\"", "\"imagez\"")).find("\"images\" is missing"),
              std::string::npos);
    EXPECT_NE(rejectionOf(edited("\"dome\"", "\"dom\"")).find("\"dome\" is missing"),
              std::string::npos);
    EXPECT_NE(rejectionOf(edited("\"directional\"", "\"spherical\""))
                  .find("lightConfiguration \"spherical\" is not supported"),
              std::string::npos);
    EXPECT_NE(rejectionOf(edited("\"y\": -1.0", "\"y\": \"down\""))
                  .find("dome.directions[1].y is missing or not a number"),
              std::string::npos);
    EXPECT_NE(rejectionOf(edited("{ \"x\": 0.0, \"y\": -1.0, \"z\": 1.0 }",
                                 "{ \"x\": 0.0, \"y\": 0.0, \"z\": 0.0 }"))
                  .find("dome.directions[1] has zero length"),
              std::string::npos);
    EXPECT_NE(rejectionOf(edited("\"filename\": \"IMG_0001.JPG\", ", ""))
                  .find("images[0] has no \"filename\""),
              std::string::npos);
    // One direction too few (the third image unskipped) and one too many (a second skipped).
    EXPECT_NE(rejectionOf(edited("\"skip\": true", "\"skip\": false"))
                  .find("holds 3 directions but more images are not skipped"),
              std::string::npos);
    EXPECT_NE(
        rejectionOf(edited("\"IMG 0002.JPG\", \"skip\": false", "\"IMG 0002.JPG\", \"skip\": true"))
            .find("holds 3 directions for 2 images not skipped"),
        std::string::npos);
}

}  // namespace
}  // namespace vpe
