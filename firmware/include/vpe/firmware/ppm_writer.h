// SPDX-License-Identifier: MIT
// writePpmAtomically: a frame as binary PPM (P6), written to a temporary file beside the
// target and renamed over it, so a reader never sees half a frame. The device build has no
// image library; PPM needs none.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace vpe::firmware {

// rgba: width·height·4 bytes, rows from the top (alpha dropped). Throws std::runtime_error
// "PATH: cannot write (…)".
void writePpmAtomically(const std::filesystem::path& path, int width, int height,
                        std::span<const std::uint8_t> rgba);

}  // namespace vpe::firmware
