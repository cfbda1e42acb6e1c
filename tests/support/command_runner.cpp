// SPDX-License-Identifier: MIT
// posix_spawn-based command runner.
#include "support/command_runner.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "support/test_data.h"

extern char** environ;

namespace vpe::testing {

std::string vpeExecutable() {
    const char* path = std::getenv("VPE_EXECUTABLE");
    if (path == nullptr) {
        throw std::runtime_error("VPE_EXECUTABLE is not set (run the tests through ctest)");
    }
    return path;
}

namespace {

std::string slurp(const std::filesystem::path& path) {
    std::ifstream stream(path);
    std::ostringstream text;
    text << stream.rdbuf();
    return text.str();
}

}  // namespace

CommandResult runCommand(const std::vector<std::string>& arguments) {
    TemporaryFolder folder;
    const std::string outPath = (folder / "stdout").string();
    const std::string errPath = (folder / "stderr").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, outPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> argv;
    for (const std::string& argument : arguments) {
        argv.push_back(const_cast<char*>(argument.c_str()));
    }
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) {
        throw std::runtime_error("cannot start " + arguments.front());
    }
    int status = 0;
    waitpid(pid, &status, 0);
    CommandResult result;
    result.exitStatus = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = slurp(outPath);
    result.err = slurp(errPath);
    return result;
}

std::vector<std::string> vpeCommand(const std::vector<std::string>& arguments) {
    std::vector<std::string> command{vpeExecutable()};
    command.insert(command.end(), arguments.begin(), arguments.end());
    return command;
}

}  // namespace vpe::testing
