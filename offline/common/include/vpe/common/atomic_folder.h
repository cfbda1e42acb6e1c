// SPDX-License-Identifier: MIT
// AtomicFolder: a command whose output is a whole folder (vpe synth, vpe quilt) writes it
// beside its final place under a temporary name and swaps it in only when complete, so a
// failure never leaves a half-written folder, and a rerun replaces its own earlier output.
#pragma once

#include <filesystem>
#include <string_view>

namespace vpe::common {

class AtomicFolder {
public:
    // `marker` (relative to the folder) is a file only this command's output has: an existing,
    // non-empty folder without it is refused (InputError) rather than replaced, since it is
    // not ours to delete. `producer` names the command in that message.
    AtomicFolder(std::filesystem::path finalPath, const std::filesystem::path& marker,
                 std::string_view producer);
    ~AtomicFolder();
    AtomicFolder(const AtomicFolder&) = delete;
    AtomicFolder& operator=(const AtomicFolder&) = delete;

    const std::filesystem::path& temporaryPath() const { return temporaryPath_; }
    // Replaces the final folder with the temporary one. Without it the destructor removes it.
    void commit();

private:
    std::filesystem::path finalPath_;
    std::filesystem::path temporaryPath_;
    bool committed_ = false;
};

}  // namespace vpe::common
