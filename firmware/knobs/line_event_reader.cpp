// SPDX-License-Identifier: MIT
// Reading GPIO line events without blocking, merged by timestamp.
#include "line_event_reader.h"

#include <cerrno>
#include <system_error>

#include <gpiod.h>
#include <poll.h>

#include "vpe/firmware/knobs/gpio_knobs.h"

namespace vpe::firmware::knobs {

namespace {

// The kernel queues 16 events per line (v1 line events); one read takes a full queue.
constexpr unsigned kEventsPerRead = 16;
// Rounds of poll + read per call: enough for a fast spin, bounded against an edge storm.
constexpr int kMaxRounds = 8;

[[noreturn]] void failRead(const std::string& chip, unsigned line, const std::string& why) {
    throw KnobsUnavailable(chip + ": cannot read events of line " + std::to_string(line) + " (" +
                           why + ")");
}

}  // namespace

std::vector<LineEdge> readPendingLineEdges(std::span<const LineEventDescriptor> descriptors,
                                           const std::string& chip) {
    if (descriptors.empty()) {
        return {};
    }
    std::vector<std::vector<LineEdge>> batches(descriptors.size());
    std::vector<pollfd> polled;
    polled.reserve(descriptors.size());
    for (const LineEventDescriptor& descriptor : descriptors) {
        polled.push_back(pollfd{descriptor.fd, POLLIN, 0});
    }

    gpiod_line_event buffer[kEventsPerRead];
    for (int round = 0; round < kMaxRounds; ++round) {
        // Timeout 0: only what is already there. Everything pending is collected before the
        // merge, so that A and B events read in different rounds are still ordered.
        const int ready = ::poll(polled.data(), polled.size(), 0);
        if (ready < 0) {
            if (errno == EINTR) {
                continue;
            }
            failRead(chip, descriptors.front().line,
                     "poll: " + std::generic_category().message(errno));
        }
        if (ready == 0) {
            break;
        }
        for (std::size_t i = 0; i < polled.size(); ++i) {
            const short revents = polled[i].revents;
            if ((revents & POLLIN) != 0) {
                const int count =
                    gpiod_line_event_read_fd_multiple(polled[i].fd, buffer, kEventsPerRead);
                if (count < 0) {
                    if (errno == EAGAIN || errno == EINTR) {
                        continue;
                    }
                    failRead(chip, descriptors[i].line, std::generic_category().message(errno));
                }
                for (int e = 0; e < count; ++e) {
                    const gpiod_line_event& event = buffer[e];
                    if (event.event_type != GPIOD_LINE_EVENT_RISING_EDGE &&
                        event.event_type != GPIOD_LINE_EVENT_FALLING_EDGE) {
                        continue;
                    }
                    batches[i].push_back(LineEdge{
                        descriptors[i].line,
                        event.event_type == GPIOD_LINE_EVENT_RISING_EDGE ? EdgeKind::kRising
                                                                         : EdgeKind::kFalling,
                        static_cast<std::int64_t>(event.ts.tv_sec) * 1'000'000'000 +
                            event.ts.tv_nsec});
                }
            } else if ((revents & POLLNVAL) != 0) {
                failRead(chip, descriptors[i].line, "descriptor not open");
            } else if ((revents & (POLLERR | POLLHUP)) != 0) {
                failRead(chip, descriptors[i].line, "descriptor in error");
            }
        }
    }
    return mergeByTimestamp(batches);
}

}  // namespace vpe::firmware::knobs
