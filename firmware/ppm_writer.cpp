// SPDX-License-Identifier: MIT
// writePpmAtomically: binary PPM through proto's temporary file and rename(2).
#include "vpe/firmware/ppm_writer.h"

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/proto/atomic_file.h"

namespace vpe::firmware {

void writePpmAtomically(const std::filesystem::path& path, int width, int height,
                        std::span<const std::uint8_t> rgba) {
    const auto pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (width < 1 || height < 1 || rgba.size() != pixels * 4) {
        throw std::invalid_argument(path.string() + ": frame size does not match its pixels");
    }
    std::vector<std::uint8_t> rgb(pixels * 3);
    for (std::size_t p = 0; p < pixels; ++p) {
        std::memcpy(&rgb[3 * p], &rgba[4 * p], 3);
    }
    const std::string header =
        "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
    proto::writeFileAtomically(
        path, {std::span<const char>(header),
               std::span<const char>(reinterpret_cast<const char*>(rgb.data()), rgb.size())});
}

}  // namespace vpe::firmware
