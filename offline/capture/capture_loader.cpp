// SPDX-License-Identifier: MIT
// Finding and reading a capture.
#include "vpe/capture/capture_loader.h"

#include <algorithm>
#include <vector>

#include "vpe/capture/capture_manifest.h"
#include "vpe/capture/light_file_reader.h"
#include "vpe/capture/relight_project_reader.h"
#include "vpe/common/input_error.h"

namespace vpe::capture {

Capture openCapture(const std::filesystem::path& path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
        if (std::filesystem::exists(path / "capture.json")) {
            return readCaptureManifest(path / "capture.json");
        }
        std::vector<std::filesystem::path> lightFiles;
        for (const auto& entry : std::filesystem::directory_iterator(path, error)) {
            if (entry.is_regular_file() && entry.path().extension() == ".lp") {
                lightFiles.push_back(entry.path());
            }
        }
        if (lightFiles.empty()) {
            throw common::InputError(path, "no capture.json or .lp light file in this folder");
        }
        if (lightFiles.size() > 1) {
            std::sort(lightFiles.begin(), lightFiles.end());
            throw common::InputError(
                path, "several .lp files (" + lightFiles[0].filename().string() + ", " +
                          lightFiles[1].filename().string() + ", ...): name the one to use");
        }
        return readLightFile(lightFiles.front());
    }
    if (!std::filesystem::exists(path, error)) {
        throw common::InputError(path, "no such file or folder");
    }
    if (path.extension() == ".json") {
        return readCaptureManifest(path);
    }
    if (path.extension() == ".relight") {
        return readRelightProject(path);
    }
    return readLightFile(path);
}

}  // namespace vpe::capture
