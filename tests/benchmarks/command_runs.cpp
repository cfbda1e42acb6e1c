// SPDX-License-Identifier: MIT
// Child processes for the command benchmarks: posix_spawn with stdout on a pipe, wait4.
#include "command_runs.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace vpe::benchmarks {

CommandRun runCommand(const std::vector<std::string>& arguments) {
    std::vector<std::string> owned = arguments;
    std::vector<char*> argv;
    for (std::string& a : owned) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    int pipeEnds[2];
    if (::pipe(pipeEnds) != 0) {
        throw std::runtime_error("cannot create a pipe");
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeEnds[0]);
    const auto start = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeEnds[1]);
    if (spawned != 0) {
        ::close(pipeEnds[0]);
        throw std::runtime_error("cannot start " + arguments[0]);
    }
    std::string output;
    char buffer[4096];
    for (ssize_t n; (n = ::read(pipeEnds[0], buffer, sizeof buffer)) > 0;) {
        output.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(pipeEnds[0]);
    int status = 0;
    rusage usage{};
    ::wait4(pid, &status, 0, &usage);
    CommandRun run;
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.peakRssMiB = static_cast<double>(usage.ru_maxrss) / 1024.0;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        throw std::runtime_error(arguments[0] + " " + arguments[1] + " failed");
    }
    while (!output.empty() && output.back() == '\n') {
        output.pop_back();
    }
    const std::size_t lastLine = output.rfind('\n');
    run.report = nlohmann::json::parse(
        lastLine == std::string::npos ? output : output.substr(lastLine + 1), nullptr, false);
    if (run.report.is_discarded()) {
        throw std::runtime_error(arguments[0] + " " + arguments[1] + " printed no JSON report");
    }
    return run;
}

double bytesOnDisk(const std::string& path) {
    if (std::filesystem::is_directory(path)) {
        double total = 0;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(path)) {
            if (entry.is_regular_file()) {
                total += static_cast<double>(entry.file_size());
            }
        }
        return total;
    }
    return static_cast<double>(std::filesystem::file_size(path));
}

}  // namespace vpe::benchmarks
