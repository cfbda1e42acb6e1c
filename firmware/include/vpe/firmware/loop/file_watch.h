// SPDX-License-Identifier: MIT
// FileWatch: tells the loop when a file was replaced. inotify on the file's folder, because
// the bake writes bundles to a temporary file and renames it over the old one (and editors
// and rsync do the same): the watch must survive the inode changing. Fires on IN_CLOSE_WRITE
// and IN_MOVED_TO of that name.
#pragma once

#include <filesystem>
#include <string>

namespace vpe::firmware {

class FileWatch {
public:
    // Throws EventLoopError when the folder cannot be watched.
    explicit FileWatch(const std::filesystem::path& file);
    ~FileWatch();
    FileWatch(const FileWatch&) = delete;
    FileWatch& operator=(const FileWatch&) = delete;

    int fd() const { return fd_; }
    // Drains pending notifications; true when one concerned the file.
    bool changed();

private:
    int fd_ = -1;
    std::string name_;
};

}  // namespace vpe::firmware
