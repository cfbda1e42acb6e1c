// SPDX-License-Identifier: MIT
// A temporary file beside the target, then rename(2).
#include "vpe/proto/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace vpe::proto {

void writeFileAtomically(const std::filesystem::path& path,
                         std::initializer_list<std::span<const char>> parts) {
    std::filesystem::path temporary = path;
    temporary += ".tmp" + std::to_string(::getpid());
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (file == nullptr) {
        throw std::runtime_error(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    }
    bool ok = true;
    for (const std::span<const char> part : parts) {
        ok = ok && std::fwrite(part.data(), 1, part.size(), file) == part.size();
    }
    const int writeErrno = errno;
    ok = (std::fclose(file) == 0) && ok;
    if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = ok ? errno : writeErrno;
        std::remove(temporary.c_str());
        throw std::runtime_error(path.string() + ": cannot write (" + std::strerror(error) + ")");
    }
}

}  // namespace vpe::proto
