// SPDX-License-Identifier: MIT
// Options most subcommands share.
#include "cli/common_options.h"

namespace vpe::cli {

void addThreadsOption(CLI::App* command, int& threads) {
    command->add_option("--threads", threads, "Worker threads (0: all cores)")
        ->capture_default_str();
}

void addJsonFlag(CLI::App* command, bool& json) {
    command->add_flag("--json", json, "End stdout with a JSON report");
}

}  // namespace vpe::cli
