// SPDX-License-Identifier: MIT
// ChildProcess: a program run in the background by the bus tests and tools (mosquitto,
// vpe-player), its stdout and stderr to files; signalled and collected by its pid only.
#pragma once

#include <chrono>
#include <csignal>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace vpe::firmware::bus::testing {

class ChildProcess {
public:
    ChildProcess() = default;
    // Starts `arguments` (the program's path first). Throws std::runtime_error when it cannot.
    ChildProcess(const std::vector<std::string>& arguments, const std::filesystem::path& out,
                 const std::filesystem::path& err);
    // A child still running is killed (SIGKILL) and collected.
    ~ChildProcess();
    ChildProcess(ChildProcess&& other) noexcept;
    ChildProcess& operator=(ChildProcess&& other) noexcept;

    pid_t pid() const { return pid_; }
    bool started() const { return pid_ > 0; }
    // Still running (not exited, not yet collected).
    bool running();
    void signal(int number);
    // Waits up to `timeout` for the exit; the exit status, 128 + N for signal N, or empty when
    // it is still running.
    std::optional<int> wait(std::chrono::milliseconds timeout);
    // SIGTERM, then SIGKILL if it has not exited after `grace`; the status.
    int stop(std::chrono::milliseconds grace = std::chrono::milliseconds(5000));

private:
    pid_t pid_ = -1;
    std::optional<int> status_;
};

}  // namespace vpe::firmware::bus::testing
