// SPDX-License-Identifier: MIT
// Nearest-rank quantiles through nth_element.
#include "vpe/common/quantile.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpe::common {

double quantile(std::vector<double> values, double share) {
    if (values.empty()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const auto rank = static_cast<std::size_t>(
        std::lround(std::clamp(share, 0.0, 1.0) * static_cast<double>(values.size() - 1)));
    const auto at = values.begin() + static_cast<std::ptrdiff_t>(rank);
    std::nth_element(values.begin(), at, values.end());
    return *at;
}

}  // namespace vpe::common
