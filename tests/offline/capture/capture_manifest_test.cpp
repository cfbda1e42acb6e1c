// SPDX-License-Identifier: MIT
// The capture manifest reader: every field it understands, its defaults, and an error naming
// the file and the key for every way a manifest can be wrong.
#include "vpe/capture/capture_manifest.h"

#include <cmath>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"

namespace vpe {
namespace {

const std::filesystem::path kFolder = "/captures/vase";
const std::filesystem::path kSource = kFolder / "capture.json";

void expectVector(const proto::Vec3d& actual, const proto::Vec3d& expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-12);
    EXPECT_NEAR(actual.y, expected.y, 1e-12);
    EXPECT_NEAR(actual.z, expected.z, 1e-12);
}

TEST(CaptureManifest, ReadsEveryField) {
    const capture::Capture capture = capture::parseCaptureManifest(R"({
        "format": "vpe-capture",
        "version": 1,
        "encoding": "linear",
        "camera": {
            "model": "pinhole",
            "fx": 1200, "fy": 1210.5, "cx": 640, "cy": -3.5,
            "rotation": [1, 0, 0, 0, -1, 0, 0, 0, -1],
            "translation": [0.1, -0.2, 2]
        },
        "lights": {"type": "point", "reference_distance": 0.75},
        "images": [
            {"file": "img/a 1.png", "light": [0.1, 0.2, 0.9], "intensity": 2.5},
            {"file": "b.png", "light": [0, 0, 3]}
        ],
        "normals": "normals.exr",
        "positions": "geometry/positions.exr",
        "plane": {"point": [0, 0, 0.1], "normal": [0, 0, 2]},
        "mask": "mask.png",
        "texel_mm": 0.25
    })",
                                                                   kSource);
    EXPECT_EQ(capture.source, kSource);
    EXPECT_EQ(capture.encoding, capture::ImageEncoding::kLinear);

    const auto* camera = std::get_if<capture::PinholeCamera>(&capture.camera);
    ASSERT_NE(camera, nullptr);
    EXPECT_EQ(camera->fx, 1200);
    EXPECT_EQ(camera->fy, 1210.5);
    EXPECT_EQ(camera->cx, 640);
    EXPECT_EQ(camera->cy, -3.5);
    EXPECT_EQ(camera->rotation, (std::array<double, 9>{1, 0, 0, 0, -1, 0, 0, 0, -1}));
    expectVector(camera->translation, {0.1, -0.2, 2});

    EXPECT_EQ(capture.lightKind, capture::LightKind::kPoint);
    EXPECT_EQ(capture.lightReferenceDistance, 0.75);
    ASSERT_EQ(capture.images.size(), 2u);
    EXPECT_EQ(capture.images[0].file, kFolder / "img" / "a 1.png");
    EXPECT_EQ(capture.images[1].file, kFolder / "b.png");
    // Point lights are positions: kept as given, not normalized.
    expectVector(capture.images[0].light, {0.1, 0.2, 0.9});
    expectVector(capture.images[1].light, {0, 0, 3});
    EXPECT_EQ(capture.images[0].intensity, 2.5);
    EXPECT_EQ(capture.images[1].intensity, 1.0);

    ASSERT_TRUE(capture.normalMap);
    EXPECT_EQ(*capture.normalMap, kFolder / "normals.exr");
    EXPECT_EQ(capture.normalEncoding, capture::NormalEncoding::kAuto);
    ASSERT_TRUE(capture.positionMap);
    EXPECT_EQ(*capture.positionMap, kFolder / "geometry" / "positions.exr");
    ASSERT_TRUE(capture.plane);
    expectVector(capture.plane->point, {0, 0, 0.1});
    expectVector(capture.plane->normal, {0, 0, 1});
    ASSERT_TRUE(capture.mask);
    EXPECT_EQ(*capture.mask, kFolder / "mask.png");
    EXPECT_EQ(capture.texelMm, 0.25);
    EXPECT_TRUE(capture.needsSurfacePositions());
}

TEST(CaptureManifest, ReadsRotationAsRowsAndNormalsAsObject) {
    const capture::Capture capture = capture::parseCaptureManifest(R"({
        "version": 1,
        "camera": {"model": "pinhole", "fx": 800, "fy": 800, "cx": 320, "cy": 240,
                   "rotation": [[0.6, -0.8, 0], [0.8, 0.6, 0], [0, 0, 1]],
                   "translation": [0, 0, 1]},
        "images": [{"file": "a.png", "light": [0, 0, 1]}],
        "normals": {"file": "n.png", "encoding": "raw"},
        "positions": "p.exr"
    })",
                                                                   kSource);
    const auto* camera = std::get_if<capture::PinholeCamera>(&capture.camera);
    ASSERT_NE(camera, nullptr);
    EXPECT_EQ(camera->rotation, (std::array<double, 9>{0.6, -0.8, 0, 0.8, 0.6, 0, 0, 0, 1}));
    ASSERT_TRUE(capture.normalMap);
    EXPECT_EQ(*capture.normalMap, kFolder / "n.png");
    EXPECT_EQ(capture.normalEncoding, capture::NormalEncoding::kRaw);
    EXPECT_FALSE(capture.plane);
}

// A valid manifest with `fields` added at the top level (they come last, so they override).
std::string withTopLevel(const std::string& fields) {
    return R"({"version": 1, "images": [{"file": "a.png", "light": [0, 0, 1]}], )" + fields + "}";
}

TEST(CaptureManifest, ReadsNormalEncodings) {
    const auto encodingOf = [](const std::string& encoding) {
        const std::string normals = R"("normals": {"file": "n.png", "encoding": ")" + encoding;
        return capture::parseCaptureManifest(withTopLevel(normals + R"("})"), kSource)
            .normalEncoding;
    };
    EXPECT_EQ(encodingOf("auto"), capture::NormalEncoding::kAuto);
    EXPECT_EQ(encodingOf("offset_rgb"), capture::NormalEncoding::kOffsetRgb);
    EXPECT_EQ(encodingOf("raw"), capture::NormalEncoding::kRaw);
}

TEST(CaptureManifest, ReadsImageEncodings) {
    const auto encodingOf = [](const std::string& encoding) {
        return capture::parseCaptureManifest(withTopLevel(R"("encoding": ")" + encoding + R"(")"),
                                             kSource)
            .encoding;
    };
    EXPECT_EQ(encodingOf("auto"), capture::ImageEncoding::kAuto);
    EXPECT_EQ(encodingOf("srgb"), capture::ImageEncoding::kSrgb);
    EXPECT_EQ(encodingOf("linear"), capture::ImageEncoding::kLinear);
}

TEST(CaptureManifest, DefaultsToOrthographicCameraAndDirectionalLights) {
    const capture::Capture capture = capture::parseCaptureManifest(
        R"({"version": 1, "images": [{"file": "a.png", "light": [0, 3, 4]}]})", kSource);
    const auto* camera = std::get_if<capture::OrthographicCamera>(&capture.camera);
    ASSERT_NE(camera, nullptr);
    EXPECT_EQ(camera->pixelSize, 1.0);
    EXPECT_EQ(capture.lightKind, capture::LightKind::kDirectional);
    EXPECT_EQ(capture.lightReferenceDistance, 1.0);
    EXPECT_EQ(capture.encoding, capture::ImageEncoding::kAuto);
    ASSERT_EQ(capture.images.size(), 1u);
    // Directional lights are directions: normalized on read.
    expectVector(capture.images[0].light, {0, 0.6, 0.8});
    EXPECT_EQ(capture.images[0].intensity, 1.0);
    EXPECT_FALSE(capture.normalMap);
    EXPECT_EQ(capture.normalEncoding, capture::NormalEncoding::kAuto);
    EXPECT_FALSE(capture.positionMap);
    EXPECT_FALSE(capture.plane);
    EXPECT_FALSE(capture.mask);
    EXPECT_FALSE(capture.needsSurfacePositions());
}

TEST(CaptureManifest, ReadsOrthographicCameraAndPartialPlane) {
    const capture::Capture capture = capture::parseCaptureManifest(R"({
        "version": 1.0,
        "camera": {"model": "orthographic", "pixel_size": 0.02},
        "lights": {"type": "directional"},
        "images": [{"file": "a.png", "light": [1e200, 0, 1e200]}],
        "plane": {}
    })",
                                                                   kSource);
    const auto* camera = std::get_if<capture::OrthographicCamera>(&capture.camera);
    ASSERT_NE(camera, nullptr);
    EXPECT_EQ(camera->pixelSize, 0.02);
    // Regression: squaring 1e200 overflowed and made the direction (0, 0, 0).
    expectVector(capture.images[0].light, {std::sqrt(0.5), 0, std::sqrt(0.5)});
    ASSERT_TRUE(capture.plane);
    expectVector(capture.plane->point, {0, 0, 0});
    expectVector(capture.plane->normal, {0, 0, 1});
}

// A manifest that is wrong in one place, and the key its error must name.
struct BadManifest {
    std::string name;  // the test's name
    std::string text;
    std::string key;
};

std::ostream& operator<<(std::ostream& stream, const BadManifest& manifest) {
    return stream << manifest.name;
}

// A valid manifest with `image` as its second image, "images[1]" in messages.
std::string withImage(const std::string& image) {
    return R"({"version": 1, "images": [{"file": "a.png", "light": [0, 0, 1]}, )" + image + "]}";
}

// A valid manifest with a pinhole camera holding `extra` besides its required fields.
std::string withPinhole(const std::string& extra) {
    return withTopLevel(
        R"("plane": {}, "camera": {"model": "pinhole", "fx": 1, "fy": 1, "cx": 0, "cy": 0, )"
        R"("translation": [0, 0, 1])" +
        (extra.empty() ? "" : ", " + extra) + "}");
}

class CaptureManifestError : public ::testing::TestWithParam<BadManifest> {};

TEST_P(CaptureManifestError, NamesFileAndKey) {
    const BadManifest& bad = GetParam();
    try {
        capture::parseCaptureManifest(bad.text, kSource);
        ADD_FAILURE() << "accepted:\n" << bad.text;
    } catch (const common::InputError& error) {
        // "/captures/vase/capture.json: images[0].light: ..."
        const std::string expected = kSource.string() + ": " + bad.key + ": ";
        EXPECT_EQ(std::string(error.what()).rfind(expected, 0), 0u)
            << "'" << error.what() << "' does not start with '" << expected << "'";
    }
}

INSTANTIATE_TEST_SUITE_P(
    CaptureManifest, CaptureManifestError,
    ::testing::Values(
        // Top level.
        BadManifest{"UnknownTopLevelKey", withTopLevel(R"("imgaes": [])"), "imgaes"},
        BadManifest{"WrongFormat", withTopLevel(R"("format": "rti")"), "format"},
        BadManifest{"FormatNotString", withTopLevel(R"("format": 1)"), "format"},
        BadManifest{"MissingVersion", R"({"images": [{"file": "a.png", "light": [0, 0, 1]}]})",
                    "version"},
        BadManifest{"WrongVersion", withTopLevel(R"("version": 2)"), "version"},
        BadManifest{"VersionNotNumber", withTopLevel(R"("version": "1")"), "version"},
        BadManifest{"BadEncoding", withTopLevel(R"("encoding": "gamma")"), "encoding"},
        BadManifest{"EncodingNotString", withTopLevel(R"("encoding": null)"), "encoding"},
        // Images.
        BadManifest{"MissingImages", R"({"version": 1})", "images"},
        BadManifest{"EmptyImages", withTopLevel(R"("images": [])"), "images"},
        BadManifest{"ImagesNotList", withTopLevel(R"("images": {"file": "a.png"})"), "images"},
        BadManifest{"ImageNotObject", withImage(R"("b.png")"), "images[1]"},
        BadManifest{"ImageWithoutFile", withImage(R"({"light": [0, 0, 1]})"), "images[1]"},
        BadManifest{"ImageWithoutLight", withImage(R"({"file": "b.png"})"), "images[1]"},
        BadManifest{"UnknownImageKey",
                    withImage(R"({"file": "b.png", "light": [0, 0, 1], "exposure": 2})"),
                    "images[1].exposure"},
        BadManifest{"EmptyFileName", withImage(R"({"file": "", "light": [0, 0, 1]})"),
                    "images[1].file"},
        BadManifest{"FileNotString", withImage(R"({"file": 7, "light": [0, 0, 1]})"),
                    "images[1].file"},
        BadManifest{"LightOfTwoNumbers", withImage(R"({"file": "b.png", "light": [0, 1]})"),
                    "images[1].light"},
        BadManifest{"LightOfFourNumbers", withImage(R"({"file": "b.png", "light": [0, 1, 2, 3]})"),
                    "images[1].light"},
        BadManifest{"LightNotList", withImage(R"({"file": "b.png", "light": "up"})"),
                    "images[1].light"},
        BadManifest{"LightComponentNotNumber",
                    withImage(R"({"file": "b.png", "light": [0, "1", 2]})"), "images[1].light[1]"},
        BadManifest{"ZeroLengthDirectionalLight",
                    withImage(R"({"file": "b.png", "light": [0, 0, 0]})"), "images[1].light"},
        BadManifest{"NegativeIntensity",
                    withImage(R"({"file": "b.png", "light": [0, 0, 1], "intensity": -1})"),
                    "images[1].intensity"},
        BadManifest{"ZeroIntensity",
                    withImage(R"({"file": "b.png", "light": [0, 0, 1], "intensity": 0})"),
                    "images[1].intensity"},
        // Lights.
        BadManifest{"LightsNotObject", withTopLevel(R"("lights": "point")"), "lights"},
        BadManifest{"UnknownLightsKey", withTopLevel(R"("lights": {"falloff": 2})"),
                    "lights.falloff"},
        BadManifest{"BadLightType", withTopLevel(R"("lights": {"type": "spot"})"), "lights.type"},
        BadManifest{"NegativeReferenceDistance",
                    withTopLevel(R"("lights": {"type": "point", "reference_distance": -2})"),
                    "lights.reference_distance"},
        // Camera.
        BadManifest{"CameraNotObject", withTopLevel(R"("camera": "pinhole")"), "camera"},
        BadManifest{"CameraWithoutModel", withTopLevel(R"("camera": {"pixel_size": 1})"), "camera"},
        BadManifest{"BadCameraModel", withTopLevel(R"("camera": {"model": "fisheye"})"),
                    "camera.model"},
        BadManifest{"CameraModelNotString", withTopLevel(R"("camera": {"model": 1})"),
                    "camera.model"},
        BadManifest{"UnknownCameraKey",
                    withTopLevel(R"("camera": {"model": "orthographic", "fx": 100})"), "camera.fx"},
        BadManifest{"NegativePixelSize",
                    withTopLevel(R"("camera": {"model": "orthographic", "pixel_size": -1})"),
                    "camera.pixel_size"},
        BadManifest{"PinholeWithoutFocalLength",
                    withTopLevel(R"("plane": {}, "camera": {"model": "pinhole", "fy": 1, )"
                                 R"("cx": 0, "cy": 0, "translation": [0, 0, 1]})"),
                    "camera.fx"},
        BadManifest{"PinholeWithoutTranslation",
                    withTopLevel(R"("plane": {}, "camera": {"model": "pinhole", "fx": 1, )"
                                 R"("fy": 1, "cx": 0, "cy": 0})"),
                    "camera.translation"},
        BadManifest{"PinholeZeroFocalLength", withPinhole(R"("fy": 0)"), "camera.fy"},
        BadManifest{"PinholeCentreNotNumber", withPinhole(R"("cx": "middle")"), "camera.cx"},
        BadManifest{"UnknownPinholeKey", withPinhole(R"("distortion": [0, 0])"),
                    "camera.distortion"},
        BadManifest{"RotationOfFourNumbers", withPinhole(R"("rotation": [1, 0, 0, 1])"),
                    "camera.rotation"},
        BadManifest{"RotationEntryNotNumber",
                    withPinhole(R"("rotation": [1, 0, 0, 0, null, 0, 0, 0, 1])"),
                    "camera.rotation[4]"},
        BadManifest{"RotationRowOfTwo",
                    withPinhole(R"("rotation": [[1, 0, 0], [0, 1], [0, 0, 1]])"),
                    "camera.rotation[1]"},
        BadManifest{"ScaledRotation", withPinhole(R"("rotation": [2, 0, 0, 0, 2, 0, 0, 0, 2])"),
                    "camera.rotation"},
        BadManifest{"ShearedRotation",
                    withPinhole(R"("rotation": [[1, 0, 0], [0.6, 0.8, 0], [0, 0, 1]])"),
                    "camera.rotation"},
        BadManifest{"PinholeWithoutPositionsOrPlane",
                    withTopLevel(R"("camera": {"model": "pinhole", "fx": 1, "fy": 1, "cx": 0, )"
                                 R"("cy": 0, "translation": [0, 0, 1]})"),
                    "camera"},
        // Geometry inputs.
        BadManifest{"NormalsNotString", withTopLevel(R"("normals": 3)"), "normals"},
        BadManifest{"NormalsWithoutFile", withTopLevel(R"("normals": {"encoding": "raw"})"),
                    "normals.file"},
        BadManifest{"UnknownNormalsKey",
                    withTopLevel(R"("normals": {"file": "n.png", "space": "world"})"),
                    "normals.space"},
        BadManifest{"BadNormalEncoding",
                    withTopLevel(R"("normals": {"file": "n.png", "encoding": "rgb"})"),
                    "normals.encoding"},
        BadManifest{"NormalEncodingNotString",
                    withTopLevel(R"("normals": {"file": "n.png", "encoding": 1})"),
                    "normals.encoding"},
        BadManifest{"EmptyPositions", withTopLevel(R"("positions": "")"), "positions"},
        BadManifest{"PlaneNotObject", withTopLevel(R"("plane": [0, 0, 1])"), "plane"},
        BadManifest{"UnknownPlaneKey", withTopLevel(R"("plane": {"offset": 1})"), "plane.offset"},
        BadManifest{"PlanePointOfTwo", withTopLevel(R"("plane": {"point": [0, 0]})"),
                    "plane.point"},
        BadManifest{"ZeroPlaneNormal", withTopLevel(R"("plane": {"normal": [0, 0, 0]})"),
                    "plane.normal"},
        BadManifest{"MaskNotString", withTopLevel(R"("mask": ["m.png"])"), "mask"},
        BadManifest{"TexelNotPositive", withTopLevel(R"("texel_mm": 0)"), "texel_mm"}),
    [](const ::testing::TestParamInfo<BadManifest>& manifest) { return manifest.param.name; });

// The message of the InputError that parsing `text` throws; a failure if it parses.
std::string rejectionOf(std::string_view text) {
    try {
        capture::parseCaptureManifest(text, kSource);
    } catch (const common::InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
}

bool startsWith(const std::string& text, const std::string& prefix) {
    return text.rfind(prefix, 0) == 0;
}

TEST(CaptureManifest, ReportsLineOfInvalidJson) {
    const std::string message = rejectionOf("{\n  \"version\": 1,\n  \"images\": [\n}\n");
    EXPECT_TRUE(startsWith(message, kSource.string() + ":4: invalid JSON: ")) << message;
    EXPECT_TRUE(startsWith(rejectionOf(""), kSource.string() + ":1: invalid JSON: "));
    EXPECT_TRUE(
        startsWith(rejectionOf("{\"version\": 1,}"), kSource.string() + ":1: invalid JSON"));
    EXPECT_TRUE(startsWith(rejectionOf("{\n\n\"version\": 1\n}\n\ntrailing"),
                           kSource.string() + ":6: invalid JSON"))
        << rejectionOf("{\n\n\"version\": 1\n}\n\ntrailing");
}

TEST(CaptureManifest, ReportsLineOfNumberBeyondDoubleRange) {
    // Regression: nlohmann::json reports this as out_of_range, not parse_error, and it
    // escaped the reader as a foreign exception.
    const std::string message = rejectionOf("{\n  \"version\": 1,\n  \"images\": 1e400\n}\n");
    EXPECT_TRUE(startsWith(message, kSource.string() + ":3: invalid JSON: number overflow"))
        << message;
}

TEST(CaptureManifest, RejectsTopLevelThatIsNotAnObject) {
    for (const std::string_view text : {"[]", "1", "\"capture\"", "null"}) {
        const std::string message = rejectionOf(text);
        EXPECT_EQ(message, kSource.string() + ": expected an object") << text;
    }
}

}  // namespace
}  // namespace vpe
