// SPDX-License-Identifier: MIT
// Runs a `vpe` command with --json and hands back its report, for the tests that chain commands
// as a technician does and read each one's figures. Header-only: the support library has no gtest.
#pragma once

#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_expectations.h"
#include "support/command_runner.h"

namespace vpe::testing {

// `vpe ARGUMENTS --json`'s report; a failure of the calling test, and an empty object, when the
// command fails.
inline nlohmann::json runWithJson(const std::vector<std::string>& arguments) {
    std::vector<std::string> withJson = arguments;
    withJson.push_back("--json");
    const CommandResult result = runCommand(vpeCommand(withJson));
    EXPECT_EQ(result.exitStatus, 0) << result.err;
    return result.exitStatus == 0 ? lastJsonLine(result.out) : nlohmann::json::object();
}

}  // namespace vpe::testing
