// SPDX-License-Identifier: MIT
// The scan manifest as JSON (nlohmann-json: header-only, on the device already for replay
// files).
#include "vpe/proto/scan_manifest.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "atomic_file.h"

namespace vpe::proto {

namespace {

using Json = nlohmann::json;

class Fields {
public:
    Fields(const Json& object, std::string source, std::string where)
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

    Fields child(const char* key) const {
        return Fields(required(key), source_, where_.empty() ? key : where_ + "." + key);
    }

private:
    const Json& object_;
    std::string source_;
    std::string where_;
};

bool plainFileName(const std::string& name) {
    return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
           name.find('\\') == std::string::npos && name.find('\0') == std::string::npos;
}

}  // namespace

std::string scanManifestJson(const ScanManifest& m) {
    Json images = Json::array();
    for (const ScanImage& image : m.images) {
        Json entry = {{"file", image.file}, {"pattern", image.pattern}};
        if (image.attempts != 1) {
            entry["attempts"] = image.attempts;
        }
        images.push_back(std::move(entry));
    }
    const Json json = {
        {"format", "vpe-scan"},
        {"version", kScanManifestVersion},
        {"created_by", m.createdBy},
        {"projector",
         {{"width", m.patterns.width},
          {"height", m.patterns.height},
          {"phase_period", m.patterns.phasePeriod},
          {"phase_steps", m.patterns.phaseSteps},
          {"latency_ms", m.projectorLatencyMs}}},
        {"camera",
         {{"width", m.camera.width},
          {"height", m.camera.height},
          {"bits", m.camera.bits},
          {"exposure_us", m.camera.exposureUs},
          {"analogue_gain", m.camera.analogueGain},
          {"source", m.camera.source}}},
    };
    // One image per line keeps the file readable and diffable.
    std::string text = json.dump(2);
    text.erase(text.find_last_of('}'));
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
        text.pop_back();
    }
    text += ",\n  \"images\": [\n";
    for (std::size_t i = 0; i < images.size(); ++i) {
        text += "    " + images[i].dump() + (i + 1 < images.size() ? ",\n" : "\n");
    }
    text += "  ]\n}\n";
    return text;
}

ScanManifest parseScanManifest(std::string_view text, const std::string& source) {
    Json json;
    try {
        json = Json::parse(text);
    } catch (const Json::exception& error) {  // parse_error, and out_of_range for 1e99999
        std::string what = error.what();
        if (const std::size_t at = what.find("] "); at != std::string::npos) {
            what = what.substr(at + 2);
        }
        throw ScanManifestError(source + ": not JSON (" + what + ")");
    }
    const Fields root(json, source, "");
    if (root.text("format", true) != "vpe-scan") {
        root.fail("format: expected \"vpe-scan\"");
    }
    const int version = root.integer("version", 0, 1 << 30);
    if (version != kScanManifestVersion) {
        root.fail("version " + std::to_string(version) + ": this reader reads version " +
                  std::to_string(kScanManifestVersion));
    }
    ScanManifest m;
    m.createdBy = root.text("created_by", false);
    const Fields projector = root.child("projector");
    m.patterns.width = projector.integer("width", 1, 16384);
    m.patterns.height = projector.integer("height", 1, 16384);
    m.patterns.phasePeriod = projector.integer("phase_period", 1, 1 << 20);
    m.patterns.phaseSteps = projector.integer("phase_steps", 1, 1 << 20);
    m.projectorLatencyMs = projector.number("latency_ms", 0, 0, 1e6);
    const Fields camera = root.child("camera");
    m.camera.width = camera.integer("width", 1, 16384);
    m.camera.height = camera.integer("height", 1, 16384);
    m.camera.bits = camera.integer("bits", 1, 16);
    if (m.camera.bits != 8 && m.camera.bits != 10) {
        camera.fail("bits: " + std::to_string(m.camera.bits) + " (8 or 10)");
    }
    m.camera.exposureUs = camera.number("exposure_us", 0, 0, 1e9);
    m.camera.analogueGain = camera.number("analogue_gain", 1, 0, 1e3);
    m.camera.source = camera.text("source", false);

    std::optional<StructuredLightSequence> sequence;
    try {
        sequence.emplace(m.patterns);
    } catch (const StructuredLightError& error) {
        projector.fail(error.what());
    }
    const Json& images = root.required("images");
    if (!images.is_array()) {
        root.fail("images: expected an array");
    }
    const std::vector<PatternSpec>& patterns = sequence->patterns();
    for (std::size_t i = 0; i < images.size(); ++i) {
        const Fields image(images[i], source, "images[" + std::to_string(i) + "]");
        ScanImage entry;
        entry.file = image.text("file", true);
        entry.pattern = image.text("pattern", true);
        entry.attempts = image.find("attempts") ? image.integer("attempts", 1, 1000) : 1;
        if (!plainFileName(entry.file)) {
            image.fail("file: '" + entry.file + "' is not a file name inside the folder");
        }
        if (i >= patterns.size()) {
            image.fail("an extra image ('" + entry.file + "'): the sequence has " +
                       std::to_string(patterns.size()) + " patterns");
        }
        if (entry.pattern != patterns[i].name()) {
            image.fail("pattern '" + entry.pattern + "', expected '" + patterns[i].name() +
                       "' (the sequence's order)");
        }
        m.images.push_back(std::move(entry));
    }
    if (m.images.size() < patterns.size()) {
        root.fail("images: " + std::to_string(m.images.size()) + " of the sequence's " +
                  std::to_string(patterns.size()) + " patterns (the first missing is '" +
                  patterns[m.images.size()].name() + "')");
    }
    return m;
}

std::filesystem::path scanFolderOf(const std::filesystem::path& folderOrFile) {
    std::error_code error;
    return std::filesystem::is_directory(folderOrFile, error) ? folderOrFile
                                                              : folderOrFile.parent_path();
}

ScanManifest readScanManifest(const std::filesystem::path& folderOrFile) {
    std::error_code error;
    const std::filesystem::path path = std::filesystem::is_directory(folderOrFile, error)
                                           ? folderOrFile / kScanManifestName
                                           : folderOrFile;
    std::ifstream stream(path, std::ios::binary);
    if (!stream) {
        throw ScanManifestError(
            path.string() + ": cannot open the scan manifest (" +
            (std::filesystem::exists(path, error) ? "unreadable" : "no such file") + ")");
    }
    std::ostringstream text;
    text << stream.rdbuf();
    return parseScanManifest(text.str(), path.string());
}

void writeScanManifest(const std::filesystem::path& folder, const ScanManifest& manifest) {
    const std::filesystem::path path = folder / kScanManifestName;
    // Checked by reading back what is written: a manifest the readers refuse is never left.
    const std::string text = scanManifestJson(manifest);
    parseScanManifest(text, path.string());
    writeFileAtomically(path, {std::span<const char>(text)});
}

std::string scanImageName(std::size_t index, const PatternSpec& pattern) {
    char number[24];
    std::snprintf(number, sizeof number, "%03zu", index);
    return std::string(number) + "-" + pattern.name() + ".pgm";
}

}  // namespace vpe::proto
