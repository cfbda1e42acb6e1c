// SPDX-License-Identifier: MIT
// AtomicOutput: temporary file plus rename.
#include "vpe/common/atomic_output.h"

#include <atomic>
#include <fstream>
#include <system_error>

#include <unistd.h>

#include "vpe/common/input_error.h"

namespace vpe::common {

namespace {

std::filesystem::path makeTemporaryPath(const std::filesystem::path& finalPath) {
    static std::atomic<unsigned> counter{0};
    const std::string name = "." + finalPath.stem().string() + ".tmp" + std::to_string(::getpid()) +
                             "-" + std::to_string(counter++) + finalPath.extension().string();
    return finalPath.parent_path() / name;
}

}  // namespace

AtomicOutput::AtomicOutput(std::filesystem::path finalPath) : finalPath_(std::move(finalPath)) {
    if (finalPath_.filename().empty()) {
        throw InputError(finalPath_, "output path names a directory, not a file");
    }
    const std::filesystem::path parent = finalPath_.parent_path();
    if (!parent.empty()) {
        std::error_code error;
        std::filesystem::create_directories(parent, error);
        if (error) {
            throw InputError(parent, "cannot create output directory: " + error.message());
        }
    }
    temporaryPath_ = makeTemporaryPath(finalPath_);
}

AtomicOutput::~AtomicOutput() {
    if (!committed_) {
        std::error_code ignored;
        std::filesystem::remove(temporaryPath_, ignored);
    }
}

void AtomicOutput::commit() {
    std::error_code error;
    std::filesystem::rename(temporaryPath_, finalPath_, error);
    if (error) {
        throw InputError(finalPath_,
                         "cannot move the finished output into place: " + error.message());
    }
    committed_ = true;
}

void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text) {
    AtomicOutput output(path);
    {
        std::ofstream stream(output.temporaryPath(), std::ios::binary);
        stream.write(text.data(), static_cast<std::streamsize>(text.size()));
        stream.close();
        if (!stream) {
            throw InputError(path, "cannot write file");
        }
    }
    output.commit();
}

}  // namespace vpe::common
