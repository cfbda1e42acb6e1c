// SPDX-License-Identifier: MIT
// The median the tests' and benchmarks' reports give of repeated measurements (header-only: the
// device's tests and the offline benchmarks both use it, and neither links the other's support).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vpe::testing {

// The middle value, or the mean of the two middle ones; 0 for no values.
inline double median(std::vector<double> values) {
    if (values.empty()) {
        return 0;
    }
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace vpe::testing
