// SPDX-License-Identifier: MIT
// AtomicOutput: every output file is written under a temporary name in its final directory
// and renamed into place only when complete, so a failure never leaves a half-written file.
#pragma once

#include <filesystem>
#include <string_view>

namespace vpe::common {

class AtomicOutput {
public:
    // Creates the parent directory if needed. The temporary name keeps the extension, since
    // image writers pick the format from it.
    explicit AtomicOutput(std::filesystem::path finalPath);
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    const std::filesystem::path& temporaryPath() const { return temporaryPath_; }
    const std::filesystem::path& finalPath() const { return finalPath_; }
    // Renames the temporary file to the final path. Without it the destructor removes it.
    void commit();

private:
    std::filesystem::path finalPath_;
    std::filesystem::path temporaryPath_;
    bool committed_ = false;
};

// Writes a whole text file atomically.
void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text);

}  // namespace vpe::common
