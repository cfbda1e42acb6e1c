// SPDX-License-Identifier: MIT
// writeFileAtomically: proto's files (scan images, manifests) and the player's frames go to a
// temporary file beside the target and are renamed over it, so that a reader never sees half a
// file.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <span>

namespace vpe::proto {

// Writes the parts one after the other. Throws std::runtime_error "PATH: cannot write (reason)".
void writeFileAtomically(const std::filesystem::path& path,
                         std::initializer_list<std::span<const char>> parts);

}  // namespace vpe::proto
