// SPDX-License-Identifier: MIT
#include "vpe/common/atomic_folder.h"

#include <string>

#include <unistd.h>

#include "vpe/common/input_error.h"

namespace vpe::common {

AtomicFolder::AtomicFolder(std::filesystem::path finalPath, const std::filesystem::path& marker,
                           std::string_view producer)
    : finalPath_(std::move(finalPath)) {
    if (std::filesystem::exists(finalPath_) && !std::filesystem::exists(finalPath_ / marker) &&
        !std::filesystem::is_empty(finalPath_)) {
        throw InputError(finalPath_, "exists and is not a " + std::string(producer) +
                                         " output: refusing to replace it");
    }
    // Beside the final folder (same file system, so the swap is a rename), hidden, and unique
    // to this process.
    temporaryPath_ = finalPath_.parent_path() / ("." + finalPath_.filename().string() +
                                                 ".partial-" + std::to_string(::getpid()));
    std::filesystem::remove_all(temporaryPath_);
    std::filesystem::create_directories(temporaryPath_);
}

AtomicFolder::~AtomicFolder() {
    if (!committed_) {
        std::error_code ignored;
        std::filesystem::remove_all(temporaryPath_, ignored);
    }
}

void AtomicFolder::commit() {
    std::error_code error;
    std::filesystem::remove_all(finalPath_, error);
    if (!error) {
        std::filesystem::rename(temporaryPath_, finalPath_, error);
    }
    if (error) {
        throw InputError(finalPath_,
                         "cannot move the finished output into place: " + error.message());
    }
    committed_ = true;
}

}  // namespace vpe::common
