// SPDX-License-Identifier: MIT
// synthesizeAndFit: the built-in synthetic capture and its fit, what the bake, show, texture and
// GPU-fidelity tests start from.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/command_runner.h"

namespace vpe::testing {

// `vpe synth --size SIZE` into CAPTURE, then `vpe fit CAPTURE/train --no-preview` into MODEL.
// A failed command fails the calling test with its stderr: call it in ASSERT_NO_FATAL_FAILURE.
inline void synthesizeAndFit(const std::filesystem::path& capture,
                             const std::filesystem::path& model, int size) {
    const CommandResult synth = runCommand(
        vpeCommand({"synth", "--out", capture.string(), "--size", std::to_string(size)}));
    ASSERT_EQ(synth.exitStatus, 0) << synth.err;
    const CommandResult fit = runCommand(
        vpeCommand({"fit", (capture / "train").string(), "--out", model.string(), "--no-preview"}));
    ASSERT_EQ(fit.exitStatus, 0) << fit.err;
}

}  // namespace vpe::testing
