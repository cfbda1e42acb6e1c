// SPDX-License-Identifier: MIT
// synthesizeAndFit: the built-in synthetic capture and its fit, what the bake, show, texture and
// GPU-fidelity tests start from; smallFittedCapture, the one their refusals share.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/command_runner.h"
#include "support/shared_test_folders.h"

namespace vpe::testing {

// `vpe synth --size SIZE [SYNTH_OPTIONS]` into CAPTURE, then `vpe fit CAPTURE/train --no-preview`
// into MODEL. A failed command fails the calling test with its stderr: call it in
// ASSERT_NO_FATAL_FAILURE.
inline void synthesizeAndFit(const std::filesystem::path& capture,
                             const std::filesystem::path& model, int size,
                             const std::vector<std::string>& synthOptions = {}) {
    std::vector<std::string> arguments{"synth", "--out", capture.string(), "--size",
                                       std::to_string(size)};
    arguments.insert(arguments.end(), synthOptions.begin(), synthOptions.end());
    const CommandResult synth = runCommand(vpeCommand(arguments));
    ASSERT_EQ(synth.exitStatus, 0) << synth.err;
    const CommandResult fit = runCommand(
        vpeCommand({"fit", (capture / "train").string(), "--out", model.string(), "--no-preview"}));
    ASSERT_EQ(fit.exitStatus, 0) << fit.err;
}

// A folder holding capture/ (`vpe synth --size 16 --rig dome`: 49 lights) and model.exr, its fit;
// made once per build of vpe and shared by the suites' refusals, which need a model to reach
// each refusal, not a good one. Under AddressSanitizer, where the refusals run alone, each
// used to synthesize and fit the suite's own capture (48² or 96², 330 lights) first.
inline const std::filesystem::path& smallFittedCapture() {
    static const std::filesystem::path folder = folderMadeOncePerVpeBuild(
        "vpe-small-fitted-capture", [](const std::filesystem::path& partial) {
            synthesizeAndFit(partial / "capture", partial / "model.exr", 16, {"--rig", "dome"});
        });
    return folder;
}

// Called from a suite's SetUpTestSuite: whether this process runs any of the suite's tests other
// than its refusals (named *BadInput* or *Refuses*), which read smallFittedCapture() and need
// none of what the suite prepares for the others. ctest runs each test in a process of its own.
inline bool suiteRunsMoreThanItsRefusals() {
    const ::testing::TestSuite* suite = ::testing::UnitTest::GetInstance()->current_test_suite();
    if (suite == nullptr) {
        return true;
    }
    for (int i = 0; i < suite->total_test_count(); ++i) {
        const ::testing::TestInfo* test = suite->GetTestInfo(i);
        const std::string name = test->name();
        if (test->should_run() && name.find("BadInput") == std::string::npos &&
            name.find("Refuses") == std::string::npos) {
            return true;
        }
    }
    return false;
}

}  // namespace vpe::testing
