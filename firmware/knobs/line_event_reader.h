// SPDX-License-Identifier: MIT
// Reading GPIO line events (libgpiod 1.6, one descriptor per line) without blocking: every
// descriptor that poll() reports readable is read with gpiod_line_event_read_fd_multiple, again
// until none is, and the batches are merged by timestamp. Private to firmware/knobs; separate
// from GpioKnobs so that tests drive it with pipes carrying the kernel's event records.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "vpe/firmware/knobs/line_edge.h"

namespace vpe::firmware::knobs {

struct LineEventDescriptor {
    unsigned line = 0;
    int fd = -1;
};

// Reads what is pending on `descriptors` (at most a bounded number of rounds, so that an edge
// storm cannot hold the loop; the rest stays readable) and returns it merged by timestamp.
// Throws KnobsUnavailable ("CHIP: cannot read events of line 17 (…)") on a read error or a
// descriptor in error.
std::vector<LineEdge> readPendingLineEdges(std::span<const LineEventDescriptor> descriptors,
                                           const std::string& chip);

}  // namespace vpe::firmware::knobs
