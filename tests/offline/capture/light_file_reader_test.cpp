// SPDX-License-Identifier: MIT
// The .lp light file reader and openCapture: what users' files look like, and how errors name them.
#include "vpe/capture/light_file_reader.h"

#include <cmath>
#include <fstream>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"

#include "support/test_data.h"

namespace vpe {
namespace {

// Absolute, so that resolved image paths are predictable on any working directory.
const std::filesystem::path kFolder = "/captures/head";
const std::filesystem::path kSource = kFolder / "dirs.lp";

double lengthOf(const proto::Vec3d& v) {
    return std::sqrt(proto::dot(v, v));
}

// The message of the InputError that parsing `text` throws; a failure if it parses.
std::string rejectionOf(std::string_view text) {
    try {
        capture::parseLightFile(text, kSource);
    } catch (const common::InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
}

// Every rejection starts "…/dirs.lp:<line>: " so that editors can jump to the line.
::testing::AssertionResult namesLine(const std::string& message, int line) {
    const std::string prefix = kSource.string() + ":" + std::to_string(line) + ": ";
    if (message.rfind(prefix, 0) == 0) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure()
           << "'" << message << "' does not start with '" << prefix << "'";
}

bool contains(const std::string& text, std::string_view part) {
    return text.find(part) != std::string::npos;
}

void writeFile(const std::filesystem::path& path, std::string_view contents) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream stream(path, std::ios::binary);
    stream << contents;
}

void expectDirection(const proto::Vec3d& actual, const proto::Vec3d& expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-12);
    EXPECT_NEAR(actual.y, expected.y, 1e-12);
    EXPECT_NEAR(actual.z, expected.z, 1e-12);
}

TEST(LightFileReader, ReadsPlainFile) {
    const capture::Capture capture =
        capture::parseLightFile("2\na.jpg 0 0 1\nb.jpg 0.6 0 0.8\n", kSource);
    EXPECT_EQ(capture.source, kSource);
    EXPECT_EQ(capture.lightKind, capture::LightKind::kDirectional);
    EXPECT_TRUE(std::holds_alternative<capture::OrthographicCamera>(capture.camera));
    EXPECT_FALSE(capture.normalMap);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].file, kFolder / "a.jpg");
    EXPECT_EQ(capture.images[1].file, kFolder / "b.jpg");
    expectDirection(capture.images[0].light, {0, 0, 1});
    expectDirection(capture.images[1].light, {0.6, 0, 0.8});
    EXPECT_EQ(capture.images[0].line, 2);
    EXPECT_EQ(capture.images[1].line, 3);
    EXPECT_EQ(capture.images[0].intensity, 1.0);
}

TEST(LightFileReader, ResolvesImagesAgainstTheFilesFolder) {
    const capture::Capture capture = capture::parseLightFile("1\na.jpg 0 0 1\n", "dirs.lp");
    EXPECT_EQ(capture.images[0].file, std::filesystem::path("a.jpg"));
}

TEST(LightFileReader, AcceptsTabs) {
    const capture::Capture capture = capture::parseLightFile("1\t\na.jpg\t0\t0\t1\n", kSource);
    ASSERT_EQ(capture.images.size(), 1u);
    EXPECT_EQ(capture.images[0].file, kFolder / "a.jpg");
    expectDirection(capture.images[0].light, {0, 0, 1});
}

TEST(LightFileReader, AcceptsCrLfLineEndings) {
    const capture::Capture capture =
        capture::parseLightFile("2\r\na.jpg 0 0 1\r\nb.jpg 0 1 0\r\n", kSource);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[1].file, kFolder / "b.jpg");
    expectDirection(capture.images[1].light, {0, 1, 0});
}

TEST(LightFileReader, AcceptsTrailingSpaces) {
    const capture::Capture capture = capture::parseLightFile("1   \na.jpg 0 0 1   \t\n", kSource);
    ASSERT_EQ(capture.images.size(), 1u);
    EXPECT_EQ(capture.images[0].file, kFolder / "a.jpg");
}

TEST(LightFileReader, AcceptsByteOrderMark) {
    const capture::Capture capture = capture::parseLightFile(
        "\xEF\xBB\xBF"
        "1\na.jpg 0 0 1\n",
        kSource);
    ASSERT_EQ(capture.images.size(), 1u);
}

TEST(LightFileReader, SkipsBlankLinesAndKeepsLineNumbers) {
    const capture::Capture capture =
        capture::parseLightFile("\n2\n\n  \na.jpg 0 0 1\n\nb.jpg 1 0 0\n\n\n  \n", kSource);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].line, 5);
    EXPECT_EQ(capture.images[1].line, 7);
}

TEST(LightFileReader, AcceptsMissingFinalNewline) {
    const capture::Capture capture = capture::parseLightFile("1\na.jpg 0 0 1", kSource);
    ASSERT_EQ(capture.images.size(), 1u);
}

TEST(LightFileReader, AcceptsImagePathsWithFolders) {
    const capture::Capture capture =
        capture::parseLightFile("2\njpg/a.jpg 0 0 1\nraw/day 1/b.tif 0 0 1\n", kSource);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].file, kFolder / "jpg" / "a.jpg");
    EXPECT_EQ(capture.images[1].file, kFolder / "raw" / "day 1" / "b.tif");
}

TEST(LightFileReader, AcceptsImagePathsWithSpaces) {
    const capture::Capture capture =
        capture::parseLightFile("1\nmy photo  01.jpg 0 0 1\n", kSource);
    ASSERT_EQ(capture.images.size(), 1u);
    // Inner blanks belong to the name, as the file system has them.
    EXPECT_EQ(capture.images[0].file, kFolder / "my photo  01.jpg");
}

TEST(LightFileReader, AcceptsScientificNotation) {
    const capture::Capture capture =
        capture::parseLightFile("1\na.jpg 6e-1 0.0E+0 8.0e-01\n", kSource);
    expectDirection(capture.images[0].light, {0.6, 0, 0.8});
}

TEST(LightFileReader, AcceptsLeadingPlusSign) {
    const capture::Capture capture = capture::parseLightFile("1\na.jpg +0.6 -0 +0.8\n", kSource);
    expectDirection(capture.images[0].light, {0.6, 0, 0.8});
}

TEST(LightFileReader, NormalizesLightVectors) {
    const capture::Capture capture =
        capture::parseLightFile("3\na.jpg 0 3 4\nb.jpg -2 -2 1\nc.jpg 0.001 0 0.001\n", kSource);
    ASSERT_EQ(capture.images.size(), 3u);
    for (const capture::CaptureImage& image : capture.images) {
        EXPECT_NEAR(lengthOf(image.light), 1.0, 1e-12);
    }
    expectDirection(capture.images[0].light, {0, 0.6, 0.8});
    expectDirection(capture.images[1].light, {-2.0 / 3, -2.0 / 3, 1.0 / 3});
    expectDirection(capture.images[2].light, {std::sqrt(0.5), 0, std::sqrt(0.5)});
}

TEST(LightFileReader, NormalizesVectorsWhoseSquaresOverflowOrUnderflow) {
    // Regression: the length was computed from squared components, which made these (0, 0, 0)
    // and "zero-length" respectively.
    const capture::Capture capture =
        capture::parseLightFile("2\na.jpg 3e200 0 4e200\nb.jpg 0 3e-5 4e-5\n", kSource);
    expectDirection(capture.images[0].light, {0.6, 0, 0.8});
    expectDirection(capture.images[1].light, {0, 0.6, 0.8});
}

TEST(LightFileReader, RejectsEmptyFile) {
    for (const std::string_view text : {"", "\n\n", "  \r\n\t\n", "\xEF\xBB\xBF"}) {
        const std::string message = rejectionOf(text);
        EXPECT_TRUE(namesLine(message, 1));
        EXPECT_TRUE(contains(message, "empty")) << message;
    }
}

TEST(LightFileReader, RejectsFirstLineThatIsNotACount) {
    for (const std::string_view text :
         {"a.jpg 0 0 1\n", "two\na.jpg 0 0 1\n", "1.5\na.jpg 0 0 1\n", "1 2\na.jpg 0 0 1\n"}) {
        const std::string message = rejectionOf(text);
        EXPECT_TRUE(namesLine(message, 1));
        EXPECT_TRUE(contains(message, "number of images")) << message;
    }
    // The count is the first line that is not blank.
    EXPECT_TRUE(namesLine(rejectionOf("\n\nx\na.jpg 0 0 1\n"), 3));
}

TEST(LightFileReader, RejectsCountOutOfRange) {
    for (const std::string_view text : {"0\n", "-1\na.jpg 0 0 1\n", "100001\na.jpg 0 0 1\n"}) {
        const std::string message = rejectionOf(text);
        EXPECT_TRUE(namesLine(message, 1));
        EXPECT_TRUE(contains(message, "out of range")) << message;
    }
    // Beyond long: not a count at all rather than a wrapped-around one.
    EXPECT_TRUE(namesLine(rejectionOf("99999999999999999999999\na.jpg 0 0 1\n"), 1));
}

TEST(LightFileReader, RejectsMoreLinesThanDeclared) {
    const std::string message = rejectionOf("2\na.jpg 0 0 1\nb.jpg 0 0 1\n\nc.jpg 0 0 1\n");
    // The first line beyond the count.
    EXPECT_TRUE(namesLine(message, 5));
    EXPECT_TRUE(contains(message, "declares 2 images but lists 3")) << message;
}

TEST(LightFileReader, RejectsFewerLinesThanDeclared) {
    const std::string message = rejectionOf("\n3\na.jpg 0 0 1\nb.jpg 0 0 1\n");
    // The line that declares the count.
    EXPECT_TRUE(namesLine(message, 2));
    EXPECT_TRUE(contains(message, "declares 3 images but lists 2")) << message;
}

TEST(LightFileReader, RejectsNonNumericComponent) {
    const std::string message = rejectionOf("2\na.jpg 0 0 1\nb.jpg 0 up 1\n");
    EXPECT_TRUE(namesLine(message, 3));
    EXPECT_TRUE(contains(message, "y component 'up'")) << message;
    EXPECT_TRUE(namesLine(rejectionOf("1\na.jpg 0 0 1x\n"), 2));
    EXPECT_TRUE(namesLine(rejectionOf("1\na.jpg 0,5 0 1\n"), 2));
    EXPECT_TRUE(namesLine(rejectionOf("1\na.jpg +-0.5 0 1\n"), 2));  // from_chars took the '-'
    EXPECT_TRUE(namesLine(rejectionOf("1\na.jpg 0x1 0 1\n"), 2));
}

TEST(LightFileReader, RejectsMissingComponent) {
    for (const std::string_view text : {"1\na.jpg 0 1\n", "1\na.jpg\n", "1\n0 0 1\n"}) {
        const std::string message = rejectionOf(text);
        EXPECT_TRUE(namesLine(message, 2));
        EXPECT_TRUE(contains(message, "expected 'image x y z'")) << message;
    }
}

TEST(LightFileReader, RejectsZeroLengthLightVector) {
    for (const std::string_view text :
         {"1\na.jpg 0 0 0\n", "1\na.jpg -0 0.0 0e5\n", "1\na.jpg 1e-10 0 0\n"}) {
        const std::string message = rejectionOf(text);
        EXPECT_TRUE(namesLine(message, 2));
        EXPECT_TRUE(contains(message, "zero-length")) << message;
    }
}

TEST(LightFileReader, RejectsNonFiniteComponents) {
    for (const std::string_view component :
         {"nan", "NaN", "-nan", "inf", "-inf", "+inf", "infinity", "1e400", "-1e999"}) {
        const std::string message =
            rejectionOf("2\na.jpg 0 0 1\nb.jpg 0 " + std::string(component) + " 1\n");
        EXPECT_TRUE(namesLine(message, 3)) << component;
        EXPECT_TRUE(contains(message, "is not a number")) << message;
    }
}

TEST(LightFileReader, ReadsFileAndPicksUpNormalsBesideIt) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "dirs.lp", "1\na.jpg 0 0 1\n");
    const capture::Capture without = capture::readLightFile(folder / "dirs.lp");
    EXPECT_EQ(without.source, folder / "dirs.lp");
    EXPECT_EQ(without.images[0].file, folder / "a.jpg");
    EXPECT_FALSE(without.normalMap);

    // Only its presence matters here; the image is decoded later.
    writeFile(folder / "normals.png", "");
    const capture::Capture with = capture::readLightFile(folder / "dirs.lp");
    ASSERT_TRUE(with.normalMap);
    EXPECT_EQ(*with.normalMap, folder / "normals.png");
    EXPECT_EQ(with.normalEncoding, capture::NormalEncoding::kOffsetRgb);
}

TEST(LightFileReader, ReportsUnreadableFile) {
    const testing::TemporaryFolder folder;
    try {
        capture::readLightFile(folder / "missing.lp");
        ADD_FAILURE() << "read a missing file";
    } catch (const common::InputError& error) {
        EXPECT_TRUE(contains(error.what(), (folder / "missing.lp").string())) << error.what();
    }
}

TEST(LightFileReader, ErrorsFromFilesNameThePath) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "dirs.lp", "2\na.jpg 0 0 1\nb.jpg 0 0 zero\n");
    try {
        capture::readLightFile(folder / "dirs.lp");
        ADD_FAILURE() << "accepted a bad component";
    } catch (const common::InputError& error) {
        EXPECT_EQ(std::string(error.what()).rfind((folder / "dirs.lp").string() + ":3: ", 0), 0u)
            << error.what();
    }
}

// The message of the InputError that opening `path` throws; a failure if it opens.
std::string openingRejectionOf(const std::filesystem::path& path) {
    try {
        capture::openCapture(path);
    } catch (const common::InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "opened " << path;
    return {};
}

TEST(OpenCapture, ReadsTheOnlyLightFileOfAFolder) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "head.lp", "1\njpg/a.jpg 0 0 1\n");
    writeFile(folder / "notes.txt", "not a light file");
    const capture::Capture capture = capture::openCapture(folder.path());
    EXPECT_EQ(capture.source, folder / "head.lp");
    ASSERT_EQ(capture.images.size(), 1u);
    EXPECT_EQ(capture.images[0].file, folder / "jpg" / "a.jpg");
}

TEST(OpenCapture, ReadsAFileNamedDirectly) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "a.lp", "1\na.jpg 0 0 1\n");
    writeFile(folder / "b.lp", "1\nb.jpg 0 0 1\n");
    EXPECT_EQ(capture::openCapture(folder / "b.lp").images[0].file, folder / "b.jpg");
    writeFile(folder / "scene.json",
              R"({"version": 1, "images": [{"file": "c.png", "light": [0, 0, 1]}]})");
    EXPECT_EQ(capture::openCapture(folder / "scene.json").images[0].file, folder / "c.png");
}

TEST(OpenCapture, RejectsFolderWithSeveralLightFiles) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "b.lp", "1\nb.jpg 0 0 1\n");
    writeFile(folder / "a.lp", "1\na.jpg 0 0 1\n");
    const std::string message = openingRejectionOf(folder.path());
    EXPECT_TRUE(contains(message, folder.path().string())) << message;
    EXPECT_TRUE(contains(message, "a.lp")) << message;
    EXPECT_TRUE(contains(message, "b.lp")) << message;
}

TEST(OpenCapture, RejectsFolderWithoutLightFile) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "a.jpg", "");
    writeFile(folder / "lp" / "dirs.lp", "1\na.jpg 0 0 1\n");  // subfolders are not searched
    const std::string message = openingRejectionOf(folder.path());
    EXPECT_TRUE(contains(message, folder.path().string())) << message;
    EXPECT_TRUE(contains(message, ".lp")) << message;
}

TEST(OpenCapture, RejectsMissingPath) {
    const testing::TemporaryFolder folder;
    for (const std::filesystem::path& path :
         {folder / "nowhere", folder / "nowhere.lp", folder / "nowhere" / "capture.json"}) {
        const std::string message = openingRejectionOf(path);
        EXPECT_TRUE(contains(message, path.string())) << message;
        EXPECT_TRUE(contains(message, "no such file")) << message;
    }
}

TEST(OpenCapture, PrefersManifestOverLightFile) {
    const testing::TemporaryFolder folder;
    writeFile(folder / "dirs.lp", "1\na.jpg 0 0 1\n");
    writeFile(folder / "capture.json", R"({
        "version": 1,
        "lights": {"type": "point"},
        "images": [{"file": "m.png", "light": [0, 0, 5]}]
    })");
    const capture::Capture capture = capture::openCapture(folder.path());
    EXPECT_EQ(capture.source, folder / "capture.json");
    EXPECT_EQ(capture.lightKind, capture::LightKind::kPoint);
    ASSERT_EQ(capture.images.size(), 1u);
    EXPECT_EQ(capture.images[0].file, folder / "m.png");
}

TEST(LightFileReader, ReadsRealCapture) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path lightFile = data / "loewenkopf" / "dirs.lp";
    if (!std::filesystem::exists(lightFile)) {
        GTEST_SKIP() << lightFile << " not found";
    }
    const capture::Capture capture = capture::openCapture(data / "loewenkopf");
    EXPECT_EQ(capture.source, lightFile);
    ASSERT_EQ(capture.images.size(), 240u);
    for (const capture::CaptureImage& image : capture.images) {
        EXPECT_EQ(image.file.parent_path().filename(), "jpg") << image.file;
        EXPECT_TRUE(std::filesystem::is_regular_file(image.file)) << image.file;
        EXPECT_NEAR(lengthOf(image.light), 1.0, 1e-12) << image.file;
    }
    EXPECT_EQ(capture.images.front().line, 2);
    EXPECT_EQ(capture.images.back().line, 241);
}

}  // namespace
}  // namespace vpe
