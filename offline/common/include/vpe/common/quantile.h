// SPDX-License-Identifier: MIT
// quantile: the value at a share of the way through a set of numbers, nearest rank.
#pragma once

#include <vector>

namespace vpe::common {

// The element of rank round(share · (n − 1)) in increasing order (share 0: the least, 0.5: the
// median, 1: the greatest); NaN for an empty set. Takes the values by copy (nth_element).
double quantile(std::vector<double> values, double share);

}  // namespace vpe::common
