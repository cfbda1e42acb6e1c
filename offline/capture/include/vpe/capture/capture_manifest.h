// SPDX-License-Identifier: MIT
// Reads a capture manifest (capture.json): what an .lp file cannot say — point lights with
// positions, a pinhole camera, the image encoding, normal, position and mask maps. The
// format is documented in docs/capture-manifest.md.
#pragma once

#include <filesystem>
#include <string_view>

#include "vpe/capture/capture.h"

namespace vpe::capture {

// Parses manifest text; `source` names it in messages and relative paths are resolved
// against its folder. Throws InputError naming the file, line or key.
Capture parseCaptureManifest(std::string_view text, const std::filesystem::path& source);

Capture readCaptureManifest(const std::filesystem::path& path);

}  // namespace vpe::capture
