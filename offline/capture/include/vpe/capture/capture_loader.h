// SPDX-License-Identifier: MIT
// openCapture: accepts what users type for CAPTURE — a folder holding one .lp file or a
// capture.json, or the path of either file, or a RelightLab project (.relight) — and reads it.
#pragma once

#include <filesystem>

#include "vpe/capture/capture.h"

namespace vpe::capture {

Capture openCapture(const std::filesystem::path& path);

}  // namespace vpe::capture
