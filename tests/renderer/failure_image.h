// SPDX-License-Identifier: MIT
// writeFailureImage: a frame test's evidence when it fails (actual, expected, difference),
// written into the working directory (ctest's: the test's build folder). PNG where the build
// has OpenImageIO (every build but the device-only one), binary PPM there (no image library on
// the device). Returns the file name written.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vpe::renderer::testing {

// rgb: width·height·3 bytes, rows from the top. `stem` without extension.
std::string writeFailureImage(const std::string& stem, int width, int height,
                              const std::vector<std::uint8_t>& rgb);

}  // namespace vpe::renderer::testing
