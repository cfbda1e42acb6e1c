// SPDX-License-Identifier: MIT
// The radiometric capture: its flat fields in their order, and a manifest that round-trips and
// refuses, in one line naming the key, what the fit could not use.
#include "vpe/proto/radiometry_capture.h"

#include <gtest/gtest.h>

#include "vpe/proto/structured_light.h"

#include "manifest_refusal.h"

namespace vpe::proto {
namespace {

RadiometryManifest smallManifest(CameraResponseKind response = CameraResponseKind::kLinear) {
    RadiometryManifest m;
    m.fields = {64, 48, 4, response, 3};
    m.camera.width = 80;
    m.camera.height = 60;
    m.camera.bits = response == CameraResponseKind::kLinear ? 10 : 8;
    m.camera.response = response;
    m.camera.exposureUs = 15000;
    m.camera.source = "simulated:test";
    m.createdBy = "test";
    const std::vector<FlatField> fields = radiometrySequence(m.fields);
    for (std::size_t i = 0; i < fields.size(); ++i) {
        m.images.push_back({radiometryImageName(i, fields[i]), fields[i].name()});
    }
    return m;
}

std::string errorOf(const std::string& json) {
    return testing::refusalOf(parseRadiometryManifest, json, "radiometry.json");
}

using testing::replaced;

TEST(RadiometrySequence, BlackWhiteThenEachPrimaryUpTheLadder) {
    const std::vector<FlatField> fields = radiometrySequence({64, 48, 4});
    ASSERT_EQ(fields.size(), 2u + 3u * 4u);
    EXPECT_EQ(fields[0].name(), "flat-black");
    EXPECT_EQ(fields[1].name(), "flat-white");
    EXPECT_EQ(fields[2].name(), "flat-red-064");
    EXPECT_EQ(fields[5].name(), "flat-red-255");
    EXPECT_EQ(fields[13].name(), "flat-blue-255");
    EXPECT_EQ((fields[6].codes(0, 64)), (std::array<std::uint8_t, 3>{0, 64, 0}));
    EXPECT_EQ((fields[1].codes(5, 64)), (std::array<std::uint8_t, 3>{255, 255, 255}));
}

TEST(RadiometrySequence, AnUnknownCameraResponseAddsABracketedRamp) {
    const std::vector<FlatField> fields =
        radiometrySequence({64, 48, 4, CameraResponseKind::kUnknown, 3});
    ASSERT_EQ(fields.size(), 2u + 12u + 3u);
    EXPECT_EQ(fields[14].name(), "ramp-e0");
    EXPECT_EQ(fields[16].name(), "ramp-e2");
    EXPECT_DOUBLE_EQ(fields[16].exposureScale(), 0.25);
    EXPECT_EQ(fields[14].codes(0, 64)[0], 0);
    EXPECT_EQ(fields[14].codes(63, 64)[1], 255);
}

TEST(RadiometrySequence, RefusesWhatMakesNoLadder) {
    EXPECT_THROW(radiometrySequence({4, 48, 4}), StructuredLightError);
    EXPECT_THROW(radiometrySequence({64, 48, 1}), StructuredLightError);
    EXPECT_THROW(radiometrySequence({64, 48, 4, CameraResponseKind::kUnknown, 2}),
                 StructuredLightError);
}

TEST(RadiometryManifest, RoundTrips) {
    for (const auto response : {CameraResponseKind::kLinear, CameraResponseKind::kUnknown}) {
        const RadiometryManifest m = smallManifest(response);
        const RadiometryManifest back =
            parseRadiometryManifest(radiometryManifestJson(m), "radiometry.json");
        EXPECT_EQ(back.fields.width, 64);
        EXPECT_EQ(back.fields.levels, 4);
        EXPECT_EQ(back.camera.bits, m.camera.bits);
        EXPECT_EQ(back.camera.response, response);
        EXPECT_DOUBLE_EQ(back.camera.exposureUs, 15000);
        ASSERT_EQ(back.images.size(), m.images.size());
        EXPECT_EQ(back.images.back().file, m.images.back().file);
    }
}

TEST(RadiometryManifest, RefusesInOneLineNamingTheKey) {
    const std::string good = radiometryManifestJson(smallManifest());
    EXPECT_EQ(errorOf(replaced(good, "\"channels\": 3", "\"channels\": 1")),
              "radiometry.json: camera: channels: 1: the radiometric capture needs a colour "
              "camera (3)");
    EXPECT_EQ(errorOf(replaced(good, "\"response\": \"linear\"", "\"response\": \"unknown\"")),
              "radiometry.json: camera: response: \"unknown\" with 10 bits: bracketing reads "
              "8-bit codes; capture raw (\"linear\") or 8-bit");
    EXPECT_EQ(errorOf(replaced(good, "\"response\": \"linear\"", "\"response\": \"srgb\"")),
              "radiometry.json: camera: response: 'srgb' (linear or unknown)");
    // A flat field missing from the sequence.
    EXPECT_EQ(
        errorOf(replaced(
            good, "    {\"file\":\"003-flat-red-128.ppm\",\"pattern\":\"flat-red-128\"},\n", "")),
        "radiometry.json: images[3]: pattern 'flat-red-191', expected 'flat-red-128' (the "
        "sequence's order)");
    const std::string lastLine =
        ",\n    {\"file\":\"013-flat-blue-255.ppm\",\"pattern\":\"flat-blue-255\"}";
    EXPECT_EQ(errorOf(replaced(good, lastLine, "")),
              "radiometry.json: images: 13 of the sequence's 14 flat fields (the first missing is "
              "'flat-blue-255')");
    EXPECT_EQ(errorOf(replaced(good, "vpe-radiometry", "vpe-scan")),
              "radiometry.json: format: expected \"vpe-radiometry\"");
}

}  // namespace
}  // namespace vpe::proto
