// SPDX-License-Identifier: MIT
// The names the tests of the `vpe` command call it by, unqualified: vpe({...}) for its argument
// list, runCommand, lastJsonLine and expectInputError. A test takes them all with
// `using namespace testing::vpe_command_names;` inside namespace vpe.
#pragma once

#include "support/cli_expectations.h"
#include "support/command_runner.h"

namespace vpe::testing::vpe_command_names {

using testing::expectInputError;
using testing::lastJsonLine;
using testing::runCommand;
inline constexpr auto& vpe = vpeCommand;

}  // namespace vpe::testing::vpe_command_names
