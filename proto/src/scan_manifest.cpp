// SPDX-License-Identifier: MIT
// The scan manifest as JSON (nlohmann-json: header-only, on the device already for replay
// files).
#include "vpe/proto/scan_manifest.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpe/proto/atomic_file.h"

#include "json_fields.h"

namespace vpe::proto {

namespace {

using detail::Json;
using Fields = detail::JsonFields;

}  // namespace

std::string scanManifestJson(const ScanManifest& m) {
    Json projector = detail::projectorJson(m.patterns, m.projectorLatencyMs);
    const StructuredLightParameters& p = m.patterns;
    // The keys of foreign sequences only where they differ from the device's, so that its
    // manifests read as they always have.
    if (p.phaseSteps > 0) {
        projector["phase_period"] = p.phasePeriod;
    }
    projector["phase_steps"] = p.phaseSteps;
    if (p.codeStep != 1) {
        projector["code_step"] = p.codeStep;
    }
    if (p.lowestGrayBit) {
        projector["lowest_gray_bit"] = *p.lowestGrayBit;
    }
    if (!p.flatFields) {
        projector["flat_fields"] = false;
    }
    return detail::manifestText(detail::manifestHead("vpe-scan", kScanManifestVersion, m.createdBy,
                                                     projector, detail::cameraJson(m.camera)),
                                m.images);
}

ScanManifest parseScanManifest(std::string_view text, const std::string& source) {
    const Json json = detail::parseManifestJson(text, source, "vpe-scan", kScanManifestVersion);
    const Fields root(json, source, "");
    ScanManifest m;
    const Fields projector = detail::readManifestHead(root, m, m.patterns);
    StructuredLightParameters& p = m.patterns;
    p.phaseSteps = projector.integer("phase_steps", 0, 1 << 20);
    if (p.phaseSteps > 0 || projector.find("phase_period")) {
        p.phasePeriod = projector.integer("phase_period", 1, 1 << 20);
    }
    if (projector.find("code_step")) {
        p.codeStep = projector.integer("code_step", 1, 16384);
    }
    if (projector.find("lowest_gray_bit")) {
        p.lowestGrayBit = projector.integer("lowest_gray_bit", 0, 31);
    }
    p.flatFields = projector.boolean("flat_fields", true);
    m.projectorLatencyMs = projector.number("latency_ms", 0, 0, 1e6);
    const Fields camera = root.child("camera");
    detail::readCameraFormat(camera, m.camera, true);
    detail::readCameraSettings(camera, m.camera);

    std::optional<StructuredLightSequence> sequence;
    try {
        sequence.emplace(m.patterns);
    } catch (const StructuredLightError& error) {
        projector.fail(error.what());
    }
    std::vector<std::string> declared;
    for (const PatternSpec& pattern : sequence->patterns()) {
        declared.push_back(pattern.name());
    }
    m.images = detail::parseImageSet(root, source, declared, "patterns");
    return m;
}

std::filesystem::path scanFolderOf(const std::filesystem::path& folderOrFile) {
    std::error_code error;
    return std::filesystem::is_directory(folderOrFile, error) ? folderOrFile
                                                              : folderOrFile.parent_path();
}

ScanManifest readScanManifest(const std::filesystem::path& folderOrFile) {
    std::filesystem::path path;
    const std::string text =
        detail::readManifestText(folderOrFile, kScanManifestName, "scan manifest", path);
    return parseScanManifest(text, path.string());
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

namespace detail {

void checkManifestHead(const JsonFields& root, const char* format, int version) {
    if (root.text("format", true) != format) {
        root.fail(std::string("format: expected \"") + format + "\"");
    }
    const int found = root.integer("version", 0, 1 << 30);
    if (found != version) {
        root.fail("version " + std::to_string(found) + ": this reader reads version " +
                  std::to_string(version));
    }
}

Json manifestHead(const char* format, int version, const std::string& createdBy,
                  const Json& projector, const Json& camera) {
    return {{"format", format},
            {"version", version},
            {"created_by", createdBy},
            {"projector", projector},
            {"camera", camera}};
}

Json parseManifestJson(std::string_view text, const std::string& source, const char* format,
                       int version) {
    Json json = parseJsonText(text, source);
    checkManifestHead(JsonFields(json, source, ""), format, version);
    return json;
}

std::string manifestText(const Json& head, const std::vector<ScanImage>& images) {
    std::string text = head.dump(2);
    text.erase(text.find_last_of('}'));
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
        text.pop_back();
    }
    text += ",\n  \"images\": [\n";
    for (std::size_t i = 0; i < images.size(); ++i) {
        Json entry = {{"file", images[i].file}, {"pattern", images[i].pattern}};
        if (images[i].attempts != 1) {
            entry["attempts"] = images[i].attempts;
        }
        text += "    " + entry.dump() + (i + 1 < images.size() ? ",\n" : "\n");
    }
    return text + "  ]\n}\n";
}

ScanImage readImageEntry(const JsonFields& image) {
    ScanImage entry;
    entry.file = image.text("file", true);
    entry.pattern = image.text("pattern", true);
    entry.attempts = image.find("attempts") ? image.integer("attempts", 1, 1000) : 1;
    if (!plainFileName(entry.file)) {
        image.fail("file: '" + entry.file + "' is not a file name inside the folder");
    }
    return entry;
}

std::vector<ScanImage> parseImageList(const JsonFields& root, const std::string& source,
                                      const std::vector<std::string>& expected, const char* what) {
    const Json& images = root.required("images");
    if (!images.is_array()) {
        root.fail("images: expected an array");
    }
    std::vector<ScanImage> list;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const JsonFields image(images[i], source, "images[" + std::to_string(i) + "]");
        ScanImage entry = readImageEntry(image);
        if (i >= expected.size()) {
            image.fail("an extra image ('" + entry.file + "'): the sequence has " +
                       std::to_string(expected.size()) + " " + what);
        }
        if (entry.pattern != expected[i]) {
            image.fail("pattern '" + entry.pattern + "', expected '" + expected[i] +
                       "' (the sequence's order)");
        }
        list.push_back(std::move(entry));
    }
    if (list.size() < expected.size()) {
        root.fail("images: " + std::to_string(list.size()) + " of the sequence's " +
                  std::to_string(expected.size()) + " " + what + " (the first missing is '" +
                  expected[list.size()] + "')");
    }
    return list;
}

std::vector<ScanImage> parseImageSet(const JsonFields& root, const std::string& source,
                                     const std::vector<std::string>& declared, const char* what) {
    const Json& images = root.required("images");
    if (!images.is_array()) {
        root.fail("images: expected an array");
    }
    // Where each declared pattern is listed (the image's index), to name the first listing of
    // a pattern listed twice.
    std::map<std::string, std::size_t, std::less<>> listedAt;
    for (const std::string& name : declared) {
        listedAt.emplace(name, images.size());
    }
    std::vector<ScanImage> list;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const JsonFields image(images[i], source, "images[" + std::to_string(i) + "]");
        ScanImage entry = readImageEntry(image);
        const auto place = listedAt.find(entry.pattern);
        if (place == listedAt.end()) {
            image.fail("pattern '" + entry.pattern + "' is not one of the declared sequence's " +
                       std::to_string(declared.size()) + " " + what);
        }
        if (place->second != images.size()) {
            image.fail("pattern '" + entry.pattern + "' again (images[" +
                       std::to_string(place->second) + "] shows it)");
        }
        place->second = i;
        list.push_back(std::move(entry));
    }
    if (list.size() < declared.size()) {
        const auto missing = std::find_if(declared.begin(), declared.end(), [&](const auto& name) {
            return listedAt.find(name)->second == images.size();
        });
        root.fail("images: " + std::to_string(list.size()) + " of the sequence's " +
                  std::to_string(declared.size()) + " " + what + " (the first missing is '" +
                  *missing + "')");
    }
    return list;
}

Json parseJsonText(std::string_view text, const std::string& source) {
    try {
        return Json::parse(text);
    } catch (const Json::exception& error) {  // parse_error, and out_of_range for 1e99999
        std::string what = error.what();
        if (const std::size_t at = what.find("] "); at != std::string::npos) {
            what = what.substr(at + 2);
        }
        throw ScanManifestError(source + ": not JSON (" + what + ")");
    }
}

std::string readManifestText(const std::filesystem::path& folderOrFile, const char* name,
                             const char* what, std::filesystem::path& path) {
    std::error_code error;
    path = std::filesystem::is_directory(folderOrFile, error) ? folderOrFile / name : folderOrFile;
    std::ifstream stream(path, std::ios::binary);
    if (!stream) {
        throw ScanManifestError(
            path.string() + ": cannot open the " + what + " (" +
            (std::filesystem::exists(path, error) ? "unreadable" : "no such file") + ")");
    }
    std::ostringstream text;
    text << stream.rdbuf();
    return text.str();
}

}  // namespace detail

}  // namespace vpe::proto
