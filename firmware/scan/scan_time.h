// SPDX-License-Identifier: MIT
// The scan clock's arithmetic (scanClockNs, nanoseconds) and its numbers in messages, shared by
// the capture loop and the scan's run.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace vpe::firmware::scan_time {

inline constexpr double kNsPerMs = 1e6;

inline double msBetween(std::int64_t fromNs, std::int64_t toNs) {
    return static_cast<double>(toNs - fromNs) / kNsPerMs;
}

inline std::int64_t nsOf(double ms) {
    return static_cast<std::int64_t>(ms * kNsPerMs);
}

// "%g": 350, 0.5, 1e+06.
inline std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

}  // namespace vpe::firmware::scan_time
