// SPDX-License-Identifier: MIT
// Where the real captures are: $VPE_DATA, else the build's default (../shared/data).
// Tests that need them skip with a message when they are absent.
#pragma once

#include <filesystem>
#include <optional>

namespace vpe::testing {

std::optional<std::filesystem::path> realDataDir();

// A fresh, empty folder under the system temporary directory, removed on destruction.
class TemporaryFolder {
public:
    TemporaryFolder();
    ~TemporaryFolder();
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::filesystem::path& name) const {
        return path_ / name;
    }

private:
    std::filesystem::path path_;
};

}  // namespace vpe::testing

// Skips the current test when the real captures are absent.
#define VPE_REQUIRE_REAL_DATA(dir)                                                         \
    const auto dir##Optional = ::vpe::testing::realDataDir();                              \
    if (!dir##Optional) {                                                                  \
        GTEST_SKIP() << "real captures not found: set VPE_DATA or provide ../shared/data"; \
    }                                                                                      \
    const std::filesystem::path dir = *dir##Optional
