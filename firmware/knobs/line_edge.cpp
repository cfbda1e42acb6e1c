// SPDX-License-Identifier: MIT
// LineEdge batches merged by timestamp.
#include "vpe/firmware/knobs/line_edge.h"

#include <algorithm>
#include <iterator>

namespace vpe::firmware::knobs {

std::vector<LineEdge> mergeByTimestamp(std::span<const std::vector<LineEdge>> batches) {
    // A handful of lines: successive two-way merges. std::merge is stable (from the first
    // range first on ties) and never reorders within a range.
    std::vector<LineEdge> merged;
    std::vector<LineEdge> next;
    for (const std::vector<LineEdge>& batch : batches) {
        next.clear();
        next.reserve(merged.size() + batch.size());
        std::merge(
            merged.begin(), merged.end(), batch.begin(), batch.end(), std::back_inserter(next),
            [](const LineEdge& a, const LineEdge& b) { return a.timestampNs < b.timestampNs; });
        merged.swap(next);
    }
    return merged;
}

}  // namespace vpe::firmware::knobs
