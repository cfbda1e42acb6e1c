// SPDX-License-Identifier: MIT
// Test data locations and temporary folders.
#include "support/test_data.h"

#include <atomic>
#include <cstdlib>
#include <random>
#include <string>

#include <unistd.h>

#include "test_paths.h"

namespace vpe::testing {

std::optional<std::filesystem::path> realDataDir() {
    std::filesystem::path dir;
    if (const char* env = std::getenv("VPE_DATA"); env != nullptr && *env != '\0') {
        dir = env;
    } else {
        dir = test_paths::defaultDataDir();
    }
    std::error_code error;
    if (std::filesystem::is_directory(dir / "synthrti", error) ||
        std::filesystem::is_directory(dir / "loewenkopf", error)) {
        return dir;
    }
    return std::nullopt;
}

TemporaryFolder::TemporaryFolder() {
    static std::atomic<unsigned> counter{0};
    std::random_device entropy;
    path_ = std::filesystem::temp_directory_path() /
            ("vpe-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(entropy()));
    std::filesystem::create_directories(path_);
}

TemporaryFolder::~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

}  // namespace vpe::testing
