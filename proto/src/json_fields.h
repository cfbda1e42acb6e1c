// SPDX-License-Identifier: MIT
// JsonFields: reading a capture manifest's JSON object key by key, each problem one
// ScanManifestError line naming the manifest, where in it, and what is wrong. Shared by the scan
// manifest (scan.json) and the radiometric capture's (radiometry.json).
#pragma once

#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/proto/scan_manifest.h"

namespace vpe::proto::detail {

using Json = nlohmann::json;

class JsonFields {
public:
    JsonFields(const Json& object, std::string source, std::string where)
        : object_(object), source_(std::move(source)), where_(std::move(where)) {
        if (!object_.is_object()) {
            fail("expected an object");
        }
    }

    [[noreturn]] void fail(const std::string& problem) const {
        throw ScanManifestError(source_ + ": " + (where_.empty() ? "" : where_ + ": ") + problem);
    }

    const Json* find(const char* key) const {
        const auto it = object_.find(key);
        return it == object_.end() ? nullptr : &*it;
    }

    const Json& required(const char* key) const {
        const Json* value = find(key);
        if (value == nullptr) {
            fail(std::string(key) + ": missing");
        }
        return *value;
    }

    int integer(const char* key, int low, int high) const {
        const Json& value = required(key);
        if (!value.is_number_integer()) {
            fail(std::string(key) + ": expected a whole number");
        }
        const auto number = value.get<long long>();
        if (number < low || number > high) {
            fail(std::string(key) + ": " + std::to_string(number) + " outside " +
                 std::to_string(low) + ".." + std::to_string(high));
        }
        return static_cast<int>(number);
    }

    double number(const char* key, double fallback, double low, double high) const {
        const Json* value = find(key);
        if (value == nullptr) {
            return fallback;
        }
        if (!value->is_number()) {
            fail(std::string(key) + ": expected a number");
        }
        const double number = value->get<double>();
        if (!std::isfinite(number) || number < low || number > high) {
            fail(std::string(key) + ": " + value->dump() + " outside [" + Json(low).dump() + ", " +
                 Json(high).dump() + "]");
        }
        return number;
    }

    bool boolean(const char* key, bool fallback) const {
        const Json* value = find(key);
        if (value == nullptr) {
            return fallback;
        }
        if (!value->is_boolean()) {
            fail(std::string(key) + ": expected true or false");
        }
        return value->get<bool>();
    }

    std::string text(const char* key, bool needed) const {
        const Json* value = needed ? &required(key) : find(key);
        if (value == nullptr) {
            return "";
        }
        if (!value->is_string()) {
            fail(std::string(key) + ": expected a string");
        }
        return value->get<std::string>();
    }

    JsonFields child(const char* key) const {
        return JsonFields(required(key), source_, where_.empty() ? key : where_ + "." + key);
    }

private:
    const Json& object_;
    std::string source_;
    std::string where_;
};

// created_by and the projector's size, the first keys of every capture manifest after its format
// and version (checkManifestHead); the projector's section is returned for the manifest's own
// keys.
template <typename Manifest, typename Parameters>
JsonFields readManifestHead(const JsonFields& root, Manifest& into, Parameters& parameters) {
    into.createdBy = root.text("created_by", false);
    JsonFields projector = root.child("projector");
    parameters.width = projector.integer("width", 1, 16384);
    parameters.height = projector.integer("height", 1, 16384);
    return projector;
}

// The projector keys every capture manifest has; a manifest adds its own (keys are written
// sorted).
template <typename Parameters>
Json projectorJson(const Parameters& parameters, double latencyMs) {
    return {{"width", parameters.width}, {"height", parameters.height}, {"latency_ms", latencyMs}};
}

// The camera keys a scan and a radiometric capture share (ScanCamera and RadiometryCamera name
// them alike): size and bits, then exposure, gain and source. Two readers, so that a capture
// can read its own keys in between, in the order its messages have always come.
// `sixteenBits`: 16 is allowed too (a scan's images imported from another tool's 16-bit PNG or
// TIFF files).
template <typename Camera>
void readCameraFormat(const JsonFields& camera, Camera& into, bool sixteenBits = false) {
    into.width = camera.integer("width", 1, 16384);
    into.height = camera.integer("height", 1, 16384);
    into.bits = camera.integer("bits", 1, 16);
    if (into.bits != 8 && into.bits != 10 && !(sixteenBits && into.bits == 16)) {
        camera.fail("bits: " + std::to_string(into.bits) +
                    (sixteenBits ? " (8, 10 or 16)" : " (8 or 10)"));
    }
}

template <typename Camera>
void readCameraSettings(const JsonFields& camera, Camera& into) {
    into.exposureUs = camera.number("exposure_us", 0, 0, 1e9);
    into.analogueGain = camera.number("analogue_gain", 1, 0, 1e3);
    into.source = camera.text("source", false);
}

// The shared camera keys as JSON; a capture adds its own (the keys are written sorted).
template <typename Camera>
Json cameraJson(const Camera& camera) {
    return {{"width", camera.width},
            {"height", camera.height},
            {"bits", camera.bits},
            {"exposure_us", camera.exposureUs},
            {"analogue_gain", camera.analogueGain},
            {"source", camera.source}};
}

// A file name inside the manifest's folder: no directory part.
inline bool plainFileName(const std::string& name) {
    return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
           name.find('\\') == std::string::npos && name.find('\0') == std::string::npos;
}

// The manifest's "format" and "version": exactly these, or a ScanManifestError.
void checkManifestHead(const JsonFields& root, const char* format, int version);

// A manifest's head: format, version, created_by, and its projector and camera sections.
Json manifestHead(const char* format, int version, const std::string& createdBy,
                  const Json& projector, const Json& camera);

// A manifest's JSON text parsed, its format and version checked (checkManifestHead).
Json parseManifestJson(std::string_view text, const std::string& source, const char* format,
                       int version);

// A manifest's text: `head` indented, then "images" with one image a line (readable, diffable).
std::string manifestText(const Json& head, const std::vector<ScanImage>& images);

// The "images" array of `root`: one entry per expected pattern name, in order, each with a plain
// file name; `what` names the sequence's items in messages ("patterns", "flat fields").
std::vector<ScanImage> parseImageList(const JsonFields& root, const std::string& source,
                                      const std::vector<std::string>& expected, const char* what);

// One entry of "images": its file (a plain name), pattern and attempts.
ScanImage readImageEntry(const JsonFields& image);

// The "images" array of `root` as a set: every image shows one of the `declared` patterns, each
// exactly once, in any order (a foreign tool's order is its own), each with a plain file name.
std::vector<ScanImage> parseImageSet(const JsonFields& root, const std::string& source,
                                     const std::vector<std::string>& declared, const char* what);

// Parses JSON text, a ScanManifestError naming `source` when it is not JSON.
Json parseJsonText(std::string_view text, const std::string& source);

// The text of FOLDER/name (or of the file itself), a ScanManifestError naming it and `what` it
// should be when it cannot be read; `path` is set to the file read.
std::string readManifestText(const std::filesystem::path& folderOrFile, const char* name,
                             const char* what, std::filesystem::path& path);

}  // namespace vpe::proto::detail
