// SPDX-License-Identifier: MIT
// Timing `vpe` commands as users run them: a child process, its wall time and peak RSS (from
// wait4), the JSON report that ends its stdout, and medians over repeated runs.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../support/median.h"

namespace vpe::benchmarks {

struct CommandRun {
    double seconds = 0;     // wall time, start to exit
    double peakRssMiB = 0;  // the child's maximum resident set
    nlohmann::json report;  // the last line of its stdout, parsed
};

// Runs arguments[0] with the rest as its arguments; stderr passes through. Throws
// std::runtime_error when it cannot start, fails, or prints no JSON report.
CommandRun runCommand(const std::vector<std::string>& arguments);

using testing::median;  // tests/support/median.h

// Bytes of a file, or of every file under a folder.
double bytesOnDisk(const std::string& path);

}  // namespace vpe::benchmarks
