// SPDX-License-Identifier: MIT
#include "child_process.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace vpe::firmware::bus::testing {

namespace {

// This process's environment, for the child. In an AddressSanitizer build the child's leak check
// at exit is switched off: GCC 12's LeakSanitizer on Debian 12 (glibc 2.36) crashes in its own
// tracer in vpe-player processes that run the bus's client ("Tracer caught signal 11" reading a
// dynamic-TLS range it recorded as 0xf7b-0x18000020…, exit status 1), a sanitizer fault, not a
// leak. The bus's code is leak-checked in process by LightBusTest all the same.
std::vector<std::string> childEnvironment() {
    std::vector<std::string> environment;
    bool asanOptions = false;
    for (char** e = environ; *e != nullptr; ++e) {
        std::string entry = *e;
#if defined(__SANITIZE_ADDRESS__)
        if (entry.rfind("ASAN_OPTIONS=", 0) == 0) {
            entry += ":detect_leaks=0";
            asanOptions = true;
        }
#endif
        environment.push_back(std::move(entry));
    }
#if defined(__SANITIZE_ADDRESS__)
    if (!asanOptions) {
        environment.emplace_back("ASAN_OPTIONS=detect_leaks=0");
    }
#else
    (void)asanOptions;
#endif
    return environment;
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& arguments,
                           const std::filesystem::path& out, const std::filesystem::path& err) {
    std::vector<std::string> copies = arguments;
    std::vector<char*> argv;
    for (std::string& a : copies) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    // The child must not inherit the test's blocked signals (vpe-player blocks its own).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
    std::vector<std::string> environment = childEnvironment();
    std::vector<char*> envp;
    for (std::string& e : environment) {
        envp.push_back(e.data());
    }
    envp.push_back(nullptr);
    const int error = posix_spawn(&pid_, argv[0], &actions, &attributes, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (error != 0) {
        pid_ = -1;
        throw std::runtime_error(arguments[0] + ": cannot start (" + std::strerror(error) + ")");
    }
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0 && !status_) {
        ::kill(pid_, SIGKILL);
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(other.pid_), status_(other.status_) {
    other.pid_ = -1;
}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
    if (this != &other) {
        if (pid_ > 0 && !status_) {
            ::kill(pid_, SIGKILL);
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
        pid_ = other.pid_;
        status_ = other.status_;
        other.pid_ = -1;
    }
    return *this;
}

bool ChildProcess::running() {
    return pid_ > 0 && !wait(std::chrono::milliseconds(0)).has_value();
}

void ChildProcess::signal(int number) {
    if (pid_ > 0 && !status_) {
        ::kill(pid_, number);
    }
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds timeout) {
    if (pid_ <= 0 || status_) {
        return status_;
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        int status = 0;
        const pid_t done = ::waitpid(pid_, &status, WNOHANG);
        if (done == pid_) {
            status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            return status_;
        }
        if (done < 0 && errno != EINTR) {
            status_ = -1;
            return status_;
        }
        if (std::chrono::steady_clock::now() >= deadline) {
            return std::nullopt;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

int ChildProcess::stop(std::chrono::milliseconds grace) {
    signal(SIGTERM);
    if (const auto status = wait(grace)) {
        return *status;
    }
    signal(SIGKILL);
    return wait(std::chrono::milliseconds(5000)).value_or(-1);
}

}  // namespace vpe::firmware::bus::testing
