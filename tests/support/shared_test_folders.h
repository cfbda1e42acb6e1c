// SPDX-License-Identifier: MIT
// Folders of the slow command-line tests that outlive a test: one made once per build of vpe and
// shared between test processes, and a scratch folder of a test's own, left to look at.
#pragma once

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "support/command_runner.h"

namespace vpe::testing {

// <temp>/<name>-<stamp of the vpe executable>, which `make` fills on first use; every test after
// it, in any process (ctest runs each test in its own), finds it made until vpe is rebuilt.
// Tests that start while it is being made wait for it (a lock beside it) instead of making their
// own: under ctest -j2 two tests of a suite used to start together and each made the whole room,
// about 30 s of both cores apiece. `make` fills a folder of this process's own that is then
// renamed into place, so a test killed while making it leaves no half-made folder.
inline std::filesystem::path folderMadeOncePerVpeBuild(
    const std::string& name, const std::function<void(const std::filesystem::path&)>& make) {
    namespace fs = std::filesystem;
    const auto stamp = fs::last_write_time(vpeExecutable()).time_since_epoch().count();
    const fs::path final =
        fs::temp_directory_path() / (name + "-" + std::to_string(stamp % 1000000007));
    if (fs::exists(final / "done")) {
        return final;
    }
    const std::string lockPath = final.string() + ".lock";
    const int lock = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock >= 0) {
        while (::flock(lock, LOCK_EX) != 0 && errno == EINTR) {
        }
    }
    if (fs::exists(final / "done")) {  // made while this test waited
        if (lock >= 0) {
            ::close(lock);
        }
        return final;
    }
    const fs::path partial = final.string() + ".partial" + std::to_string(::getpid());
    fs::remove_all(partial);
    make(partial);
    std::ofstream(partial / "done") << "ok\n";
    std::error_code error;
    fs::rename(partial, final, error);
    if (error) {
        fs::remove_all(partial);  // another test made it first (one without the lock)
    }
    if (lock >= 0) {
        ::close(lock);  // releases the lock
    }
    return final;
}

// <temp>/<name>-<process id>, empty: a scratch folder of the test's own.
inline std::filesystem::path scratchFolder(const std::string& name) {
    namespace fs = std::filesystem;
    const fs::path folder = fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

}  // namespace vpe::testing
