// SPDX-License-Identifier: MIT
// writePpmAtomically: binary PPM through a temporary file and rename(2).
#include "vpe/firmware/ppm_writer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

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
    std::filesystem::path temporary = path;
    temporary += ".tmp" + std::to_string(::getpid());
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
        throw std::runtime_error(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    }
    bool ok = std::fwrite(header.data(), 1, header.size(), file) == header.size() &&
              std::fwrite(rgb.data(), 1, rgb.size(), file) == rgb.size();
    const int writeErrno = errno;
    ok = (std::fclose(file) == 0) && ok;
    if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = ok ? errno : writeErrno;
        std::remove(temporary.c_str());
        throw std::runtime_error(path.string() + ": cannot write (" + std::strerror(error) + ")");
    }
}

}  // namespace vpe::firmware
