// SPDX-License-Identifier: MIT
// Reads a RelightLab project (.relight, JSON) as a capture: its images ("folder" + "images")
// lit from its dome's "directions", in the frame of .lp files (x right, y up the image, z
// towards the camera). docs/relight-export.md lists the fields this relies on.
#pragma once

#include <filesystem>
#include <string_view>

#include "vpe/capture/capture.h"

namespace vpe::capture {

// Parses project text. `source` names the file in messages and anchors "folder". Images
// marked "skip" have no direction; those not "visible" have one but are left out, as
// RelightLab's ImageSet does. Throws InputError naming the file and what is wrong.
Capture parseRelightProject(std::string_view text, const std::filesystem::path& source);

Capture readRelightProject(const std::filesystem::path& path);

}  // namespace vpe::capture
