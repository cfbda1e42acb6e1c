// SPDX-License-Identifier: MIT
// Options most subcommands share, worded the same everywhere.
#pragma once

#include <CLI/CLI.hpp>

namespace vpe::cli {

// --threads N: worker threads (0: all cores).
void addThreadsOption(CLI::App* command, int& threads);

// --json: end stdout with a JSON report (printJson).
void addJsonFlag(CLI::App* command, bool& json);

}  // namespace vpe::cli
