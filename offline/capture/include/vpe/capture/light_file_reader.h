// SPDX-License-Identifier: MIT
// Reads an RTI light position file (.lp): line 1 holds N, then N lines "image x y z" with
// the direction towards the light (normalized on read). Tolerates tabs, CRLF, trailing
// spaces, a UTF-8 byte-order mark, blank lines and image paths with folders or spaces.
#pragma once

#include <filesystem>
#include <string_view>

#include "vpe/capture/capture.h"

namespace vpe::capture {

// Parses .lp text. `source` names the file in error messages; image paths are resolved
// against its folder. Throws InputError naming the file and line.
Capture parseLightFile(std::string_view text, const std::filesystem::path& source);

// Reads and parses a .lp file; also picks up normals.png beside it (SynthRTI convention).
Capture readLightFile(const std::filesystem::path& path);

}  // namespace vpe::capture
