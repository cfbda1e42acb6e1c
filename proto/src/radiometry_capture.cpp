// SPDX-License-Identifier: MIT
// The radiometric capture's flat fields and its manifest (see the header).
#include "vpe/proto/radiometry_capture.h"

#include <cmath>
#include <cstdio>

#include "vpe/proto/atomic_file.h"
#include "vpe/proto/structured_light.h"

#include "json_fields.h"

namespace vpe::proto {

namespace {

using detail::Json;
using Fields = detail::JsonFields;

constexpr const char* kChannelNames[3] = {"red", "green", "blue"};

const char* responseName(CameraResponseKind kind) {
    return kind == CameraResponseKind::kLinear ? "linear" : "unknown";
}

}  // namespace

std::string FlatField::name() const {
    switch (kind) {
        case FlatFieldKind::kBlack:
            return "flat-black";
        case FlatFieldKind::kWhite:
            return "flat-white";
        case FlatFieldKind::kPrimary: {
            char text[32];
            std::snprintf(text, sizeof text, "flat-%s-%03d", kChannelNames[channel % 3], code);
            return text;
        }
        case FlatFieldKind::kRamp:
            return "ramp-e" + std::to_string(exposureStop);
    }
    return "?";
}

double FlatField::exposureScale() const {
    return kind == FlatFieldKind::kRamp ? std::ldexp(1.0, -exposureStop) : 1.0;
}

std::array<std::uint8_t, 3> FlatField::codes(int x, int width) const {
    switch (kind) {
        case FlatFieldKind::kBlack:
            return {0, 0, 0};
        case FlatFieldKind::kWhite:
            return {255, 255, 255};
        case FlatFieldKind::kPrimary: {
            std::array<std::uint8_t, 3> codes{0, 0, 0};
            codes[static_cast<std::size_t>(channel)] = static_cast<std::uint8_t>(code);
            return codes;
        }
        case FlatFieldKind::kRamp: {
            const auto level =
                static_cast<std::uint8_t>(std::lround(255.0 * x / std::max(1, width - 1)));
            return {level, level, level};
        }
    }
    return {0, 0, 0};
}

std::vector<FlatField> radiometrySequence(const RadiometryParameters& p) {
    if (p.width < 8 || p.width > 16384 || p.height < 8 || p.height > 16384) {
        throw StructuredLightError("radiometry: the projector is " + std::to_string(p.width) + "x" +
                                   std::to_string(p.height) + ", outside 8..16384");
    }
    if (p.levels < 2 || p.levels > 64) {
        throw StructuredLightError("radiometry: " + std::to_string(p.levels) +
                                   " levels per primary, outside 2..64");
    }
    const bool bracket = p.cameraResponse == CameraResponseKind::kUnknown;
    if (bracket && (p.bracketStops < 3 || p.bracketStops > 8)) {
        throw StructuredLightError("radiometry: " + std::to_string(p.bracketStops) +
                                   " bracket stops, outside 3..8");
    }
    std::vector<FlatField> fields{{FlatFieldKind::kBlack}, {FlatFieldKind::kWhite}};
    for (int channel = 0; channel < 3; ++channel) {
        int previous = 0;
        for (int k = 1; k <= p.levels; ++k) {
            const auto code = static_cast<int>(std::lround(255.0 * k / p.levels));
            if (code == previous) {
                continue;  // more levels than codes apart: each code once
            }
            previous = code;
            fields.push_back({FlatFieldKind::kPrimary, channel, code});
        }
    }
    if (bracket) {
        for (int stop = 0; stop < p.bracketStops; ++stop) {
            fields.push_back({FlatFieldKind::kRamp, 0, 0, stop});
        }
    }
    return fields;
}

std::string radiometryManifestJson(const RadiometryManifest& m) {
    Json camera = detail::cameraJson(m.camera);
    camera["channels"] = m.camera.channels;
    camera["response"] = responseName(m.camera.response);
    Json projector = detail::projectorJson(m.fields, m.projectorLatencyMs);
    projector["levels"] = m.fields.levels;
    projector["bracket_stops"] = m.fields.bracketStops;
    return detail::manifestText(detail::manifestHead("vpe-radiometry", kRadiometryManifestVersion,
                                                     m.createdBy, projector, camera),
                                m.images);
}

RadiometryManifest parseRadiometryManifest(std::string_view text, const std::string& source) {
    const Json json =
        detail::parseManifestJson(text, source, "vpe-radiometry", kRadiometryManifestVersion);
    const Fields root(json, source, "");
    RadiometryManifest m;
    const Fields projector = detail::readManifestHead(root, m, m.fields);
    m.fields.levels = projector.integer("levels", 1, 1 << 20);
    m.fields.bracketStops =
        projector.find("bracket_stops") ? projector.integer("bracket_stops", 0, 1 << 20) : 5;
    m.projectorLatencyMs = projector.number("latency_ms", 0, 0, 1e6);
    const Fields camera = root.child("camera");
    detail::readCameraFormat(camera, m.camera);
    m.camera.channels = camera.integer("channels", 1, 4);
    if (m.camera.channels != 3) {
        camera.fail("channels: " + std::to_string(m.camera.channels) +
                    ": the radiometric capture needs a colour camera (3)");
    }
    const std::string response = camera.text("response", true);
    if (response == "linear") {
        m.camera.response = CameraResponseKind::kLinear;
    } else if (response == "unknown") {
        m.camera.response = CameraResponseKind::kUnknown;
        if (m.camera.bits != 8) {
            camera.fail(
                "response: \"unknown\" with 10 bits: bracketing reads 8-bit codes; "
                "capture raw (\"linear\") or 8-bit");
        }
    } else {
        camera.fail("response: '" + response + "' (linear or unknown)");
    }
    m.fields.cameraResponse = m.camera.response;
    detail::readCameraSettings(camera, m.camera);

    std::vector<FlatField> fields;
    try {
        fields = radiometrySequence(m.fields);
    } catch (const StructuredLightError& error) {
        projector.fail(error.what());
    }
    std::vector<std::string> expected;
    for (const FlatField& field : fields) {
        expected.push_back(field.name());
    }
    m.images = detail::parseImageList(root, source, expected, "flat fields");
    return m;
}

RadiometryManifest readRadiometryManifest(const std::filesystem::path& folderOrFile) {
    std::filesystem::path path;
    const std::string text = detail::readManifestText(folderOrFile, kRadiometryManifestName,
                                                      "radiometry manifest", path);
    return parseRadiometryManifest(text, path.string());
}

void writeRadiometryManifest(const std::filesystem::path& folder, const RadiometryManifest& m) {
    const std::filesystem::path path = folder / kRadiometryManifestName;
    const std::string text = radiometryManifestJson(m);
    parseRadiometryManifest(text, path.string());  // never leave one the readers refuse
    writeFileAtomically(path, {std::span<const char>(text)});
}

std::string radiometryImageName(std::size_t index, const FlatField& field) {
    char number[24];
    std::snprintf(number, sizeof number, "%03zu", index);
    return std::string(number) + "-" + field.name() + ".ppm";
}

}  // namespace vpe::proto
