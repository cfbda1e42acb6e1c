// SPDX-License-Identifier: MIT
// RateLimitedLog: a burst, then one line per interval, and a count of what was left out.
#include "vpe/firmware/loop/rate_limited_log.h"

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

TEST(RateLimitedLogTest, WritesABurstThenOneLinePerInterval) {
    std::vector<std::string> lines;
    RateLimitedLog log([&](const std::string& line) { lines.push_back(line); }, 3, 10 * kSecond);
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(log.write("line " + std::to_string(i), 100 * kSecond), i < 3);
    }
    EXPECT_EQ(lines, (std::vector<std::string>{"line 0", "line 1", "line 2"}));
    EXPECT_FALSE(log.write("early", 109 * kSecond));
    EXPECT_TRUE(log.write("later", 110 * kSecond));
    EXPECT_EQ(lines.back(), "later (8 earlier not logged)");
    EXPECT_FALSE(log.write("again", 111 * kSecond));
    EXPECT_EQ(log.suppressed(), 9u);

    // 25 s later: two intervals earned, not more.
    EXPECT_TRUE(log.write("a", 135 * kSecond));
    EXPECT_EQ(lines.back(), "a (1 earlier not logged)");
    EXPECT_TRUE(log.write("b", 135 * kSecond));
    EXPECT_FALSE(log.write("c", 135 * kSecond));
}

TEST(RateLimitedLogTest, AQuietSpellRefillsOnlyTheBurst) {
    std::vector<std::string> lines;
    RateLimitedLog log([&](const std::string& line) { lines.push_back(line); }, 2, kSecond);
    log.write("1", 0);
    log.write("2", 0);
    EXPECT_FALSE(log.write("3", 0));
    // An hour of silence: the bucket is full again, with 2 lines, not 3600.
    int written = 0;
    for (int i = 0; i < 10; ++i) {
        written += log.write("x", 3600 * kSecond) ? 1 : 0;
    }
    EXPECT_EQ(written, 2);
    // A clock going backwards earns nothing and breaks nothing.
    EXPECT_FALSE(log.write("back", 10 * kSecond));
}

}  // namespace
}  // namespace vpe::firmware
