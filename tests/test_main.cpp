// SPDX-License-Identifier: MIT
// The main of every GoogleTest binary (cmake/VpeTests.cmake). As gtest_main's, but a run in
// which every test was skipped exits 77, which ctest reports as skipped: ctest runs a whole
// suite in one process (cmake/VpeDiscoverTests.cmake), where matching gtest's "[  SKIPPED ]"
// in the output would also hide a failure beside the skip.
#include <gtest/gtest.h>

namespace {

constexpr int kAllSkippedExitStatus = 77;  // the ctest SKIP_RETURN_CODE the discovery sets

}  // namespace

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    const int status = RUN_ALL_TESTS();
    const ::testing::UnitTest& run = *::testing::UnitTest::GetInstance();
    if (status == 0 && run.test_to_run_count() > 0 &&
        run.skipped_test_count() == run.test_to_run_count()) {
        return kAllSkippedExitStatus;
    }
    return status;
}
