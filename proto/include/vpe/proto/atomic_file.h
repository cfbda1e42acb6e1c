// SPDX-License-Identifier: MIT
// AtomicFile and writeFileAtomically: every output file, on both sides (the offline tools'
// models, images and bundles; the device's scan images, manifests and frames), is written under
// a temporary name beside its target and renamed into place only when complete, so that a
// reader never sees half a file and a failure leaves none.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <span>
#include <string_view>

namespace vpe::proto {

// For writers that take a path (an image library, a mesh exporter): write temporaryPath(),
// then commit().
class AtomicFile {
public:
    // What a missing parent folder means: the offline tools make it; the device writes only
    // into folders it made itself, so there a missing one is a failure of the write.
    enum class MissingFolder { kCreate, kLeave };

    // The temporary name keeps the extension, since image writers pick the format from it.
    // Throws InputError naming the path.
    explicit AtomicFile(std::filesystem::path finalPath,
                        MissingFolder missing = MissingFolder::kCreate);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::filesystem::path& temporaryPath() const { return temporaryPath_; }
    const std::filesystem::path& finalPath() const { return finalPath_; }
    // Renames the temporary file to the final path. Without it the destructor removes it.
    // Throws InputError naming the final path.
    void commit();

private:
    std::filesystem::path finalPath_;
    std::filesystem::path temporaryPath_;
    bool committed_ = false;
};

// Writes the parts one after the other into an existing folder. Throws InputError "PATH: cannot
// write (reason)", also for a folder that is missing.
void writeFileAtomically(const std::filesystem::path& path,
                         std::initializer_list<std::span<const char>> parts);

// A whole text file, the folder made if it is missing.
void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text);

}  // namespace vpe::proto
