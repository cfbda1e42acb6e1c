// SPDX-License-Identifier: MIT
// Capture manifest reader (nlohmann::json).
#include "vpe/capture/capture_manifest.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::capture {

namespace {

using Json = nlohmann::json;

// Finds the byte where parsing stops. A number beyond double range fails as out_of_range,
// which unlike parse_error carries no position, so the text is parsed again to find it.
class JsonErrorLocator : public nlohmann::json_sax<Json> {
public:
    std::size_t byte = 0;

    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return true; }
    bool key(string_t&) override { return true; }
    bool end_object() override { return true; }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t position, const std::string&, const Json::exception&) override {
        byte = position;
        return false;
    }
};

class ManifestReader {
public:
    explicit ManifestReader(std::filesystem::path source) : source_(std::move(source)) {}

    // An empty key is the manifest itself.
    [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
        throw common::InputError(source_, key.empty() ? problem : key + ": " + problem);
    }

    void requireObject(const Json& value, const std::string& key,
                       std::initializer_list<std::string_view> allowed) const {
        if (!value.is_object()) {
            fail(key, "expected an object");
        }
        for (const auto& item : value.items()) {
            if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
                fail(key.empty() ? item.key() : key + "." + item.key(), "unknown key");
            }
        }
    }

    double number(const Json& value, const std::string& key) const {
        if (!value.is_number() || !std::isfinite(value.get<double>())) {
            fail(key, "expected a finite number");
        }
        return value.get<double>();
    }

    double positiveNumber(const Json& value, const std::string& key) const {
        const double result = number(value, key);
        if (!(result > 0)) {
            fail(key, "must be positive");
        }
        return result;
    }

    std::string string(const Json& value, const std::string& key) const {
        if (!value.is_string()) {
            fail(key, "expected a string");
        }
        return value.get<std::string>();
    }

    Vec3d vector(const Json& value, const std::string& key) const {
        if (!value.is_array() || value.size() != 3) {
            fail(key, "expected 3 numbers");
        }
        return {number(value[0], key + "[0]"), number(value[1], key + "[1]"),
                number(value[2], key + "[2]")};
    }

    std::filesystem::path file(const Json& value, const std::string& key) const {
        const std::string name = string(value, key);
        if (name.empty()) {
            fail(key, "empty file name");
        }
        return source_.parent_path() / std::filesystem::path(name).make_preferred();
    }

    CameraModel camera(const Json& value) const {
        if (!value.is_object() || !value.contains("model")) {
            fail("camera", "expected an object with a 'model'");
        }
        const std::string model = string(value["model"], "camera.model");
        if (model == "orthographic") {
            requireObject(value, "camera", {"model", "pixel_size"});
            OrthographicCamera camera;
            if (value.contains("pixel_size")) {
                camera.pixelSize = positiveNumber(value["pixel_size"], "camera.pixel_size");
            }
            return camera;
        }
        if (model == "pinhole") {
            requireObject(value, "camera",
                          {"model", "fx", "fy", "cx", "cy", "rotation", "translation"});
            PinholeCamera camera;
            for (const char* key : {"fx", "fy", "cx", "cy", "translation"}) {
                if (!value.contains(key)) {
                    fail(std::string("camera.") + key, "missing");
                }
            }
            camera.fx = positiveNumber(value["fx"], "camera.fx");
            camera.fy = positiveNumber(value["fy"], "camera.fy");
            camera.cx = number(value["cx"], "camera.cx");
            camera.cy = number(value["cy"], "camera.cy");
            camera.translation = vector(value["translation"], "camera.translation");
            if (value.contains("rotation")) {
                camera.rotation = rotation(value["rotation"]);
            }
            return camera;
        }
        fail("camera.model", "expected 'orthographic' or 'pinhole', found '" + model + "'");
    }

    std::array<double, 9> rotation(const Json& value) const {
        // Accepts 9 numbers row-major or 3 rows of 3.
        std::vector<double> entries;
        if (value.is_array() && value.size() == 3 && value[0].is_array()) {
            for (std::size_t r = 0; r < 3; ++r) {
                const Vec3d row = vector(value[r], "camera.rotation[" + std::to_string(r) + "]");
                entries.insert(entries.end(), {row.x, row.y, row.z});
            }
        } else if (value.is_array() && value.size() == 9) {
            for (std::size_t i = 0; i < 9; ++i) {
                entries.push_back(number(value[i], "camera.rotation[" + std::to_string(i) + "]"));
            }
        } else {
            fail("camera.rotation", "expected 9 numbers or 3 rows of 3");
        }
        std::array<double, 9> r{};
        std::copy(entries.begin(), entries.end(), r.begin());
        // Rows must be orthonormal: a scaled or sheared matrix is a calibration mistake.
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                const double d =
                    r[3 * i] * r[3 * j] + r[3 * i + 1] * r[3 * j + 1] + r[3 * i + 2] * r[3 * j + 2];
                if (std::fabs(d - (i == j ? 1.0 : 0.0)) > 1e-4) {
                    fail("camera.rotation", "is not a rotation (rows are not orthonormal)");
                }
            }
        }
        return r;
    }

private:
    std::filesystem::path source_;
};

int lineOfByte(std::string_view text, std::size_t byte) {
    byte = std::min(byte, text.size());
    return 1 +
           static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(byte), '\n'));
}

}  // namespace

Capture parseCaptureManifest(std::string_view text, const std::filesystem::path& source) {
    Json root;
    try {
        root = Json::parse(text.begin(), text.end());
    } catch (const Json::parse_error& error) {
        // The library's message ends with its own description of the problem.
        std::string what = error.what();
        const std::size_t colon = what.rfind(": ");
        what = colon == std::string::npos ? what : what.substr(colon + 2);
        throw common::InputError(source, lineOfByte(text, error.byte), "invalid JSON: " + what);
    } catch (const Json::out_of_range& error) {
        // Only a number beyond double range ("1e400") gets here; the message follows the
        // library's "[json.exception.out_of_range.406] " prefix.
        std::string what = error.what();
        const std::size_t bracket = what.find("] ");
        what = bracket == std::string::npos ? what : what.substr(bracket + 2);
        JsonErrorLocator locator;
        Json::sax_parse(text.begin(), text.end(), &locator);
        throw common::InputError(source, lineOfByte(text, locator.byte), "invalid JSON: " + what);
    }
    const ManifestReader reader(source);
    reader.requireObject(root, "",
                         {"format", "version", "encoding", "camera", "lights", "images", "normals",
                          "positions", "plane", "mask", "texel_mm"});
    if (root.contains("format") && reader.string(root["format"], "format") != "vpe-capture") {
        reader.fail("format", "expected 'vpe-capture'");
    }
    if (!root.contains("version")) {
        reader.fail("version", "missing (this reader understands version 1)");
    }
    if (reader.number(root["version"], "version") != 1) {
        reader.fail("version", "unsupported version (this reader understands version 1)");
    }

    Capture capture;
    capture.source = source;
    if (root.contains("encoding")) {
        const std::string encoding = reader.string(root["encoding"], "encoding");
        if (encoding == "auto") {
            capture.encoding = ImageEncoding::kAuto;
        } else if (encoding == "srgb") {
            capture.encoding = ImageEncoding::kSrgb;
        } else if (encoding == "linear") {
            capture.encoding = ImageEncoding::kLinear;
        } else {
            reader.fail("encoding",
                        "expected 'auto', 'srgb' or 'linear', found '" + encoding + "'");
        }
    }
    if (root.contains("camera")) {
        capture.camera = reader.camera(root["camera"]);
    }
    if (root.contains("lights")) {
        const Json& lights = root["lights"];
        reader.requireObject(lights, "lights", {"type", "reference_distance"});
        const std::string type =
            lights.contains("type") ? reader.string(lights["type"], "lights.type") : "directional";
        if (type == "directional") {
            capture.lightKind = LightKind::kDirectional;
        } else if (type == "point") {
            capture.lightKind = LightKind::kPoint;
        } else {
            reader.fail("lights.type", "expected 'directional' or 'point', found '" + type + "'");
        }
        if (lights.contains("reference_distance")) {
            capture.lightReferenceDistance =
                reader.positiveNumber(lights["reference_distance"], "lights.reference_distance");
        }
    }
    if (!root.contains("images") || !root["images"].is_array() || root["images"].empty()) {
        reader.fail("images", "expected a non-empty list of images");
    }
    const Json& images = root["images"];
    for (std::size_t i = 0; i < images.size(); ++i) {
        const std::string key = "images[" + std::to_string(i) + "]";
        reader.requireObject(images[i], key, {"file", "light", "intensity"});
        if (!images[i].contains("file") || !images[i].contains("light")) {
            reader.fail(key, "needs 'file' and 'light'");
        }
        CaptureImage image;
        image.file = reader.file(images[i]["file"], key + ".file");
        image.light = reader.vector(images[i]["light"], key + ".light");
        if (capture.lightKind == LightKind::kDirectional) {
            const std::optional<Vec3d> direction = unitDirection(image.light);
            if (!direction) {
                reader.fail(key + ".light", "zero-length light vector");
            }
            image.light = *direction;
        }
        if (images[i].contains("intensity")) {
            image.intensity = reader.positiveNumber(images[i]["intensity"], key + ".intensity");
        }
        capture.images.push_back(std::move(image));
    }
    if (root.contains("normals")) {
        const Json& normals = root["normals"];
        if (normals.is_object()) {
            reader.requireObject(normals, "normals", {"file", "encoding"});
            if (!normals.contains("file")) {
                reader.fail("normals.file", "missing");
            }
            capture.normalMap = reader.file(normals["file"], "normals.file");
            if (normals.contains("encoding")) {
                const std::string encoding = reader.string(normals["encoding"], "normals.encoding");
                if (encoding == "offset_rgb") {
                    capture.normalEncoding = NormalEncoding::kOffsetRgb;
                } else if (encoding == "raw") {
                    capture.normalEncoding = NormalEncoding::kRaw;
                } else if (encoding != "auto") {
                    reader.fail("normals.encoding",
                                "expected 'auto', 'offset_rgb' or 'raw', found '" + encoding + "'");
                }
            }
        } else {
            capture.normalMap = reader.file(normals, "normals");
        }
    }
    if (root.contains("positions")) {
        capture.positionMap = reader.file(root["positions"], "positions");
    }
    if (root.contains("plane")) {
        reader.requireObject(root["plane"], "plane", {"point", "normal"});
        SurfacePlane plane;
        if (root["plane"].contains("point")) {
            plane.point = reader.vector(root["plane"]["point"], "plane.point");
        }
        if (root["plane"].contains("normal")) {
            plane.normal = reader.vector(root["plane"]["normal"], "plane.normal");
        }
        const std::optional<Vec3d> normal = unitDirection(plane.normal);
        if (!normal) {
            reader.fail("plane.normal", "zero-length vector");
        }
        plane.normal = *normal;
        capture.plane = plane;
    }
    if (root.contains("mask")) {
        capture.mask = reader.file(root["mask"], "mask");
    }
    if (root.contains("texel_mm")) {
        capture.texelMm = reader.positiveNumber(root["texel_mm"], "texel_mm");
    }
    if (std::holds_alternative<PinholeCamera>(capture.camera) && !capture.positionMap &&
        !capture.plane) {
        reader.fail("camera", "a pinhole camera needs 'positions' or 'plane' to place the surface");
    }
    return capture;
}

Capture readCaptureManifest(const std::filesystem::path& path) {
    return parseCaptureManifest(text::readTextFile(path, "capture manifest"), path);
}

}  // namespace vpe::capture
