// SPDX-License-Identifier: MIT
// Where the tests and benchmarks find the repository's files and the programs this build made.
// The paths are absolute and differ per clone, so they live in one generated source
// (tests/paths/CMakeLists.txt), not in every test source's compile flags: the compile cache
// (scripts/lib/compile-cache.sh) hashes flags as written, and a path among them made each
// test source of a fresh clone compile again.
#pragma once

namespace vpe::test_paths {

// The repository's root.
const char* sourceDir();
// The real captures' default folder: ../shared/data beside the repository ($VPE_DATA overrides
// it, tests/support/test_data.cpp).
const char* defaultDataDir();
// The built vpe-player and vpe_write_test_bundle.
const char* playerPath();
const char* writeTestBundlePath();
// The built vpe; "" in the device-only build, which has none.
const char* vpeExecutablePath();

}  // namespace vpe::test_paths
