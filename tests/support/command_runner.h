// SPDX-License-Identifier: MIT
// Runs the `vpe` executable as a user would and captures its exit status and output.
#pragma once

#include <string>
#include <vector>

namespace vpe::testing {

struct CommandResult {
    int exitStatus = -1;  // -1 when it did not exit normally (signal: a crash)
    std::string out;
    std::string err;
};

// Path of the vpe executable under test (from $VPE_EXECUTABLE, set by ctest).
std::string vpeExecutable();

CommandResult runCommand(const std::vector<std::string>& arguments);

// The `vpe` executable followed by the arguments, for runCommand.
std::vector<std::string> vpeCommand(const std::vector<std::string>& arguments);

}  // namespace vpe::testing
