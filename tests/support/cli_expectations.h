// SPDX-License-Identifier: MIT
// What every `vpe` command owes its user on bad input: exit status 2 and exactly one line on
// stderr, "vpe: ...", naming what is wrong; and the --json report. Header-only: the support
// library has no gtest.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/command_runner.h"

namespace vpe::testing {

inline void expectInputError(const CommandResult& result,
                             const std::vector<std::string>& mentions) {
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_EQ(result.err.rfind("vpe: ", 0), 0u) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    if (!result.err.empty()) {
        EXPECT_EQ(result.err.back(), '\n') << result.err;
    }
    for (const std::string& mention : mentions) {
        EXPECT_NE(result.err.find(mention), std::string::npos)
            << "'" << mention << "' not in: " << result.err;
    }
}

// The JSON object `--json` ends stdout with (its last non-empty line).
inline nlohmann::json lastJsonLine(const std::string& out) {
    std::string text = out;
    while (!text.empty() && text.back() == '\n') {
        text.pop_back();
    }
    const std::size_t newline = text.rfind('\n');
    return nlohmann::json::parse(newline == std::string::npos ? text : text.substr(newline + 1));
}

}  // namespace vpe::testing
