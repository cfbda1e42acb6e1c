// SPDX-License-Identifier: MIT
// LineEdge: one GPIO line event as libgpiod reports it (line offset, rising or falling, kernel
// timestamp) and as a replay file records it; and the merge of per-line batches into one
// timeline (libgpiod 1.6 has one event queue, one descriptor, per line).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace vpe::firmware::knobs {

enum class EdgeKind : std::uint8_t { kFalling, kRising };

struct LineEdge {
    unsigned line = 0;
    EdgeKind kind = EdgeKind::kRising;
    std::int64_t timestampNs = 0;  // CLOCK_MONOTONIC

    bool operator==(const LineEdge&) const = default;
};

// Merges batches, each in its own line's order (the kernel's queue: ascending time), into one
// sequence by ascending timestamp. Each batch's own order is kept as is, and on equal timestamps
// the earlier batch comes first, so the result is deterministic.
std::vector<LineEdge> mergeByTimestamp(std::span<const std::vector<LineEdge>> batches);

}  // namespace vpe::firmware::knobs
