// SPDX-License-Identifier: MIT
// Line edges: per-line batches merged by timestamp; and the non-blocking reader on pipes that
// carry the kernel's event records (struct gpioevent_data), read by libgpiod itself.
#include "vpe/firmware/knobs/line_edge.h"

#include <array>
#include <chrono>
#include <random>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/gpio.h>
#include <unistd.h>

#include "vpe/firmware/knobs/gpio_knobs.h"

#include "knobs/line_event_reader.h"

namespace vpe::firmware::knobs {
namespace {

constexpr EdgeKind kRise = EdgeKind::kRising;
constexpr EdgeKind kFall = EdgeKind::kFalling;

TEST(LineEdgeTest, MergesBatchesByTimestamp) {
    const std::vector<std::vector<LineEdge>> batches = {
        {{17, kFall, 10}, {17, kRise, 40}, {17, kFall, 41}},
        {{27, kFall, 20}, {27, kRise, 30}, {27, kFall, 50}},
        {},
        {{22, kFall, 5}},
    };
    const std::vector<LineEdge> merged = mergeByTimestamp(batches);
    const std::vector<LineEdge> expected = {{22, kFall, 5},  {17, kFall, 10}, {27, kFall, 20},
                                            {27, kRise, 30}, {17, kRise, 40}, {17, kFall, 41},
                                            {27, kFall, 50}};
    EXPECT_EQ(merged, expected);
    EXPECT_TRUE(mergeByTimestamp({}).empty());
}

TEST(LineEdgeTest, TiesKeepTheEarlierBatchFirstAndEachLinesOrder) {
    const std::vector<std::vector<LineEdge>> batches = {
        {{1, kFall, 7}, {1, kRise, 7}},
        {{2, kFall, 7}, {2, kRise, 7}},
    };
    const std::vector<LineEdge> expected = {
        {1, kFall, 7}, {1, kRise, 7}, {2, kFall, 7}, {2, kRise, 7}};
    EXPECT_EQ(mergeByTimestamp(batches), expected);
}

TEST(LineEdgeTest, MergingRandomBatchesGivesASortedInterleaving) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<std::vector<LineEdge>> batches(1 + trial % 5);
        std::size_t total = 0;
        for (std::size_t line = 0; line < batches.size(); ++line) {
            std::int64_t t = 0;
            const int count = static_cast<int>(rng() % 40);
            for (int i = 0; i < count; ++i) {
                t += static_cast<std::int64_t>(rng() % 4);  // ties across lines happen
                batches[line].push_back(
                    LineEdge{static_cast<unsigned>(line), i % 2 ? kRise : kFall, t});
            }
            total += batches[line].size();
        }
        const std::vector<LineEdge> merged = mergeByTimestamp(batches);
        ASSERT_EQ(merged.size(), total);
        std::vector<std::size_t> next(batches.size(), 0);
        for (std::size_t i = 0; i < merged.size(); ++i) {
            if (i > 0) {
                ASSERT_LE(merged[i - 1].timestampNs, merged[i].timestampNs);
            }
            // Each line's edges come out in its own order.
            const unsigned line = merged[i].line;
            ASSERT_EQ(merged[i], batches[line][next[line]++]);
        }
    }
}

// A pipe standing in for a line's event descriptor: the records the kernel writes.
class EventPipe {
public:
    EventPipe() { EXPECT_EQ(::pipe2(fds_.data(), O_NONBLOCK | O_CLOEXEC), 0); }
    ~EventPipe() {
        ::close(fds_[0]);
        ::close(fds_[1]);
    }
    EventPipe(const EventPipe&) = delete;
    EventPipe& operator=(const EventPipe&) = delete;

    void write(std::uint64_t timestampNs, bool rising) {
        gpioevent_data data{};
        data.timestamp = timestampNs;
        data.id = rising ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE;
        ASSERT_EQ(::write(fds_[1], &data, sizeof data), static_cast<ssize_t>(sizeof data));
    }
    void writeBytes(const void* bytes, std::size_t size) {
        ASSERT_EQ(::write(fds_[1], bytes, size), static_cast<ssize_t>(size));
    }
    int readEnd() const { return fds_[0]; }
    void closeWriteEnd() {
        ::close(fds_[1]);
        fds_[1] = ::open("/dev/null", O_WRONLY | O_CLOEXEC);  // keeps the destructor simple
    }

private:
    std::array<int, 2> fds_{-1, -1};
};

TEST(LineEventReaderTest, DrainsEveryReadableLineAndMergesByTimestamp) {
    EventPipe a;
    EventPipe b;
    EventPipe quiet;
    // A and B of one encoder, turned clockwise: A falls, B falls, A rises, B rises; and more
    // than one read's worth (16) on A to drain.
    a.write(1'000, false);
    b.write(2'000, false);
    a.write(3'000, true);
    b.write(4'000'000'001ULL, true);
    for (int i = 0; i < 40; ++i) {
        a.write(5'000'000'000ULL + static_cast<std::uint64_t>(i), i % 2 == 0 ? false : true);
    }
    const std::vector<LineEventDescriptor> descriptors = {
        {17, a.readEnd()}, {27, b.readEnd()}, {22, quiet.readEnd()}};
    const auto start = std::chrono::steady_clock::now();
    const std::vector<LineEdge> edges = readPendingLineEdges(descriptors, "gpiochip0");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));  // no wait
    ASSERT_EQ(edges.size(), 44U);
    EXPECT_EQ(edges[0], (LineEdge{17, kFall, 1'000}));
    EXPECT_EQ(edges[1], (LineEdge{27, kFall, 2'000}));
    EXPECT_EQ(edges[2], (LineEdge{17, kRise, 3'000}));
    EXPECT_EQ(edges[3], (LineEdge{27, kRise, 4'000'000'001LL}));
    EXPECT_EQ(edges[43], (LineEdge{17, kRise, 5'000'000'039LL}));
    // Nothing left: a second read returns at once with nothing.
    EXPECT_TRUE(readPendingLineEdges(descriptors, "gpiochip0").empty());
}

TEST(LineEventReaderTest, ABrokenDescriptorIsOneLineNamingChipAndLine) {
    EventPipe a;
    a.closeWriteEnd();  // the read end hangs up
    const std::vector<LineEventDescriptor> descriptors = {{17, a.readEnd()}};
    try {
        readPendingLineEdges(descriptors, "gpiochip0");
        FAIL() << "no error";
    } catch (const KnobsUnavailable& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos);
        EXPECT_EQ(message, "gpiochip0: cannot read events of line 17 (descriptor in error)");
    }
    // A short record (not a whole event) is a read error, not a crash.
    EventPipe b;
    const char half[4] = {1, 2, 3, 4};
    b.writeBytes(half, sizeof half);
    const std::vector<LineEventDescriptor> shortRecord = {{27, b.readEnd()}};
    EXPECT_THROW(readPendingLineEdges(shortRecord, "gpiochip0"), KnobsUnavailable);
}

}  // namespace
}  // namespace vpe::firmware::knobs
