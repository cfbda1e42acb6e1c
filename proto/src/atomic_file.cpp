// SPDX-License-Identifier: MIT
// A temporary file beside the target, then rename(2).
#include "vpe/proto/atomic_file.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

#include "vpe/proto/input_error.h"

namespace vpe::proto {

namespace {

// Hidden, in the target's folder (so that the move is a rename), unique to this process and
// to each file it writes at once.
std::filesystem::path makeTemporaryPath(const std::filesystem::path& finalPath) {
    static std::atomic<unsigned> counter{0};
    const std::string name = "." + finalPath.stem().string() + ".tmp" + std::to_string(::getpid()) +
                             "-" + std::to_string(counter++) + finalPath.extension().string();
    return finalPath.parent_path() / name;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path finalPath, MissingFolder missing)
    : finalPath_(std::move(finalPath)) {
    if (finalPath_.filename().empty()) {
        throw InputError(finalPath_, "output path names a directory, not a file");
    }
    const std::filesystem::path parent = finalPath_.parent_path();
    if (!parent.empty() && missing == MissingFolder::kCreate) {
        std::error_code error;
        std::filesystem::create_directories(parent, error);
        if (error) {
            throw InputError(parent, "cannot create output directory: " + error.message());
        }
    }
    temporaryPath_ = makeTemporaryPath(finalPath_);
}

AtomicFile::~AtomicFile() {
    if (!committed_) {
        std::error_code ignored;
        std::filesystem::remove(temporaryPath_, ignored);
    }
}

void AtomicFile::commit() {
    std::error_code error;
    std::filesystem::rename(temporaryPath_, finalPath_, error);
    if (error) {
        throw InputError(finalPath_,
                         "cannot move the finished output into place: " + error.message());
    }
    committed_ = true;
}

namespace {

void writeParts(AtomicFile& output, std::initializer_list<std::span<const char>> parts) {
    const std::filesystem::path& path = output.finalPath();
    std::FILE* file = std::fopen(output.temporaryPath().c_str(), "wb");
    if (file == nullptr) {
        throw InputError(path, std::string("cannot write (") + std::strerror(errno) + ")");
    }
    bool ok = true;
    for (const std::span<const char> part : parts) {
        ok = ok && std::fwrite(part.data(), 1, part.size(), file) == part.size();
    }
    int error = errno;
    if (std::fclose(file) != 0 && ok) {
        ok = false;
        error = errno;
    }
    if (!ok) {
        throw InputError(path, std::string("cannot write (") + std::strerror(error) + ")");
    }
    output.commit();
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path,
                         std::initializer_list<std::span<const char>> parts) {
    AtomicFile output(path, AtomicFile::MissingFolder::kLeave);
    writeParts(output, parts);
}

void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text) {
    AtomicFile output(path);
    writeParts(output, {std::span<const char>(text.data(), text.size())});
}

}  // namespace vpe::proto
