// SPDX-License-Identifier: MIT
// ScanManifest: what a scan capture folder holds (proto/SCAN.md) — the projector's pattern
// sequence, the camera that photographed it and one image per pattern, in any order. Written by
// the device (vpe-player --scan) and the simulator (vpe synth-procam), read by vpe scan and
// vpe calibrate: one definition of the folder for both sides.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/proto/input_error.h"
#include "vpe/proto/structured_light.h"

namespace vpe::proto {

inline constexpr const char* kScanManifestName = "scan.json";
inline constexpr int kScanManifestVersion = 1;

struct ScanCamera {
    int width = 0, height = 0;  // pixels of every image
    int bits = 8;               // per sample: 8 (maxval 255), 10 (maxval 1023) or 16 (imported)
    double exposureUs = 0;      // fixed for the whole sequence (0: not known)
    double analogueGain = 1;    // fixed likewise
    std::string source;         // "libcamera:<id>" or "simulated:<scene>"
};

struct ScanImage {
    std::string file;     // a file name inside the folder (no directory part)
    std::string pattern;  // PatternSpec::name() of the pattern it shows
    int attempts = 1;     // captures it took to pass the device's frame check
};

struct ScanManifest {
    StructuredLightParameters patterns;  // the projector's size and the phase settings
    ScanCamera camera;
    std::vector<ScanImage> images;  // one per pattern of the sequence, in any order
    std::string createdBy;          // "vpe-player", "vpe synth-procam", ...
    double projectorLatencyMs = 0;  // the wait after showing a pattern, before capturing
};

// Every problem with a manifest, one line: "<path>: <problem>".
class ScanManifestError : public InputError {
public:
    using InputError::InputError;
};

// JSON text (indented, one image per line).
std::string scanManifestJson(const ScanManifest& manifest);

// Parses and checks: format "vpe-scan", version 1, a valid sequence, a camera size in
// 1..16384 and bits 8, 10 or 16, and images that each name a pattern of the declared sequence,
// every pattern exactly once (in any order), with plain file names. `source` names the manifest in
// errors. Throws ScanManifestError.
ScanManifest parseScanManifest(std::string_view json, const std::string& source);

// DIR/scan.json (or a path to the manifest itself).
ScanManifest readScanManifest(const std::filesystem::path& folderOrFile);
// Writes DIR/scan.json atomically.
void writeScanManifest(const std::filesystem::path& folder, const ScanManifest& manifest);

// The manifest's folder for `folderOrFile` (the file's parent when given a file).
std::filesystem::path scanFolderOf(const std::filesystem::path& folderOrFile);

// The file name of image `index` showing `pattern`: "NNN-<pattern name>.pgm" ("007-gray-x-b5.pgm"),
// as the device and the simulator both name them.
std::string scanImageName(std::size_t index, const PatternSpec& pattern);

}  // namespace vpe::proto
