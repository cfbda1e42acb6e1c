// SPDX-License-Identifier: MIT
#include "vpe/firmware/loop/file_watch.h"

#include <cerrno>
#include <cstring>

#include <sys/inotify.h>
#include <unistd.h>

#include "vpe/firmware/loop/event_loop.h"

namespace vpe::firmware {

FileWatch::FileWatch(const std::filesystem::path& file)
    : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)), name_(file.filename().string()) {
    if (fd_ < 0) {
        throw EventLoopError(file.string() +
                             ": cannot watch (inotify_init1: " + std::strerror(errno) + ")");
    }
    std::filesystem::path folder = file.parent_path();
    if (folder.empty()) {
        folder = ".";
    }
    if (::inotify_add_watch(fd_, folder.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO) < 0) {
        const int error = errno;
        ::close(fd_);
        throw EventLoopError(folder.string() + ": cannot watch folder (" + std::strerror(error) +
                             ")");
    }
}

FileWatch::~FileWatch() {
    ::close(fd_);
}

bool FileWatch::changed() {
    bool ours = false;
    alignas(inotify_event) char buffer[4096];
    for (;;) {
        const ssize_t length = ::read(fd_, buffer, sizeof buffer);
        if (length <= 0) {
            return ours;
        }
        for (ssize_t offset = 0; offset < length;) {
            const auto* event = reinterpret_cast<const inotify_event*>(buffer + offset);
            if (event->len > 0 && name_ == event->name) {
                ours = true;
            }
            offset += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
        }
    }
}

}  // namespace vpe::firmware
