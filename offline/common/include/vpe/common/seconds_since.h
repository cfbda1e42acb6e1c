// SPDX-License-Identifier: MIT
// secondsSince: the seconds since a steady-clock instant, what the reports time their steps with.
#pragma once

#include <chrono>

namespace vpe::common {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vpe::common
