// SPDX-License-Identifier: MIT
// PlayerTest: runs the real vpe-player binary on the GLES tests' vase bundle (160 × 120) in a
// temporary folder, capturing status, stdout and stderr.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "vpe/renderer/gles/headless_egl_platform.h"

#include "gles_test_bundle.h"
#include "test_paths.h"

namespace vpe::firmware::testing {

namespace fs = std::filesystem;

struct PlayerRun {
    int status = -1;
    std::string out, err;
};

inline std::string readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

inline std::string quoted(const std::string& text) {
    std::string out = "'";
    for (const char c : text) {
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return out + "'";
}

class PlayerTest : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = fs::temp_directory_path() /
                  ("vpe-player-test-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(folder_);
        const std::vector<std::byte> bytes = renderer::testing::buildGlesTestBundle();
        bundleBytes_.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        bundle_ = writeFile("scene.vpeb", bundleBytes_);
        // Unpaced, and a drift that starts at once and moves fast: a few frames show motion.
        headless_ = writeFile("headless.toml", std::string("[display]\nbackend = \"headless\"\n") +
                                                   kFastRender + kFastDrift);
    }
    void TearDown() override { fs::remove_all(folder_); }

    fs::path writeFile(const std::string& name, const std::string& contents) {
        const fs::path path = folder_ / name;
        std::ofstream(path, std::ios::binary) << contents;
        return path;
    }

    PlayerRun play(const std::vector<std::string>& arguments) {
        std::string command = quoted(test_paths::playerPath());
        for (const std::string& a : arguments) {
            command += " " + quoted(a);
        }
        const fs::path out = folder_ / "stdout.txt", err = folder_ / "stderr.txt";
        command += " >" + quoted(out.string()) + " 2>" + quoted(err.string());
        PlayerRun run;
        const int status = std::system(command.c_str());
        run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        run.out = readAll(out);
        run.err = readAll(err);
        return run;
    }

    // Starts vpe-player in the background (stdout/stderr to files); finish() collects it.
    pid_t spawn(const std::vector<std::string>& arguments) {
        std::vector<std::string> argv{test_paths::playerPath()};
        argv.insert(argv.end(), arguments.begin(), arguments.end());
        std::vector<char*> pointers;
        for (std::string& a : argv) {
            pointers.push_back(a.data());
        }
        pointers.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, (folder_ / "spawn-out.txt").c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&actions, 2, (folder_ / "spawn-err.txt").c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644);
        pid_t pid = -1;
        const int error =
            posix_spawn(&pid, pointers[0], &actions, nullptr, pointers.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        return error == 0 ? pid : -1;
    }
    PlayerRun finish(pid_t pid) {
        int status = 0;
        ::waitpid(pid, &status, 0);
        PlayerRun run;
        run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        run.out = readAll(folder_ / "spawn-out.txt");
        run.err = readAll(folder_ / "spawn-err.txt");
        return run;
    }
    std::string spawnedErr() const { return readAll(folder_ / "spawn-err.txt"); }

    // Exit status 2 and exactly one line on stderr, containing `needle`.
    void expectOneLineError(const PlayerRun& run, const std::string& needle) {
        EXPECT_EQ(run.status, 2) << run.err;
        ASSERT_FALSE(run.err.empty());
        EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
        EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    }

    static constexpr const char* kFastRender = "[render]\nrate = 0\n";
    static constexpr const char* kFastDrift =
        "[idle]\nquiet_s = 0\nhandover_s = 0\nperiod_s = 0.5\n";

    fs::path folder_, bundle_, headless_;
    std::string bundleBytes_;
};

// Why the tests that draw are skipped here: no headless OpenGL ES 3.1 context, and the
// platform's error; nothing where one can be made.
inline std::optional<std::string> noHeadlessGles() {
    try {
        renderer::gles::createHeadlessEglPlatform();
        return std::nullopt;
    } catch (const renderer::gles::GraphicsError& error) {
        return std::string("no headless OpenGL ES 3.1: ") + error.what();
    }
}

}  // namespace vpe::firmware::testing
