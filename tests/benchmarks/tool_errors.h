// SPDX-License-Identifier: MIT
// How a benchmark tool that reads the user's files ends on an exception, as vpe's own commands
// do (offline/cli/main.cpp): a bad input (common::InputError) is its message and exit status 2,
// anything else is an internal error and exit status 1.
#pragma once

#include <cstdio>
#include <exception>

#include "vpe/common/input_error.h"

namespace vpe::benchmarks {

// Runs `work`; 0 when it returns.
template <typename Work>
int exitStatusOf(Work&& work) {
    try {
        work();
    } catch (const common::InputError& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 2;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "internal error: %s\n", error.what());
        return 1;
    }
    return 0;
}

}  // namespace vpe::benchmarks
