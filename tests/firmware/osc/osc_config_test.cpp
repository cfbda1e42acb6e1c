// SPDX-License-Identifier: MIT
// OscConfig: the [osc] section's defaults, values, and one-line refusals naming file:osc.key.
#include "vpe/firmware/osc/osc_config.h"

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "vpe/firmware/board_config.h"

namespace vpe::firmware {
namespace {

OscConfig parse(const std::string& text) {
    const toml::table root = toml::parse(text);
    return parseOscConfig(root["osc"].as_table(), "board.toml");
}

std::string errorOf(const std::string& text) {
    try {
        parse(text);
    } catch (const BoardConfigError& error) {
        return error.what();
    }
    return "(no error)";
}

TEST(OscConfigTest, DefaultsToLoopbackPort9000) {
    const OscConfig absent = parseOscConfig(nullptr, "board.toml");
    EXPECT_TRUE(absent.enabled);
    EXPECT_EQ(absent.address, "127.0.0.1");
    EXPECT_EQ(absent.port, 9000);

    const OscConfig empty = parse("[osc]\n");
    EXPECT_TRUE(empty.enabled);
    EXPECT_EQ(empty.address, "127.0.0.1");
    EXPECT_EQ(empty.port, 9000);
}

TEST(OscConfigTest, ReadsEveryKey) {
    const OscConfig config =
        parse("[osc]\nenabled = false\naddress = \"0.0.0.0\"\nport = 7000\nprotocol = \"udp\"\n");
    EXPECT_FALSE(config.enabled);
    EXPECT_EQ(config.address, "0.0.0.0");
    EXPECT_EQ(config.port, 7000);
    EXPECT_EQ(parse("[osc]\naddress = \"::1\"\n").address, "::1");
    EXPECT_EQ(parse("[osc]\naddress = \"192.168.1.20\"\nport = 65535\n").port, 65535);
    EXPECT_EQ(parse("[osc]\nport = 1\n").port, 1);
}

TEST(OscConfigTest, RefusesBadValuesWithOneLine) {
    EXPECT_EQ(errorOf("[osc]\nhost = \"x\"\n"),
              "board.toml:osc.host: unknown key (known: address, enabled, port, protocol)");
    EXPECT_EQ(errorOf("[osc]\nport = 0\n"), "board.toml:osc.port: expected 1..65535, got 0");
    EXPECT_EQ(errorOf("[osc]\nport = 70000\n"),
              "board.toml:osc.port: expected 1..65535, got 70000");
    EXPECT_EQ(errorOf("[osc]\nport = \"9000\"\n"),
              "board.toml:osc.port: expected an integer, got a string");
    EXPECT_EQ(errorOf("[osc]\nport = 9000.5\n"),
              "board.toml:osc.port: expected an integer, got a number");
    EXPECT_EQ(errorOf("[osc]\nenabled = \"yes\"\n"),
              "board.toml:osc.enabled: expected a boolean, got a string");
    EXPECT_EQ(errorOf("[osc]\naddress = \"localhost\"\n"),
              "board.toml:osc.address: expected a numeric IPv4 or IPv6 address (\"127.0.0.1\", "
              "\"0.0.0.0\", \"::1\"), got \"localhost\"");
    EXPECT_EQ(errorOf("[osc]\naddress = \"127.0.0.256\"\n").substr(0, 30),
              "board.toml:osc.address: expect");
    EXPECT_EQ(errorOf("[osc]\naddress = 127\n"),
              "board.toml:osc.address: expected a string, got an integer");
    EXPECT_EQ(errorOf("[osc]\nprotocol = \"tcp\"\n"),
              "board.toml:osc.protocol: expected \"udp\" (the only protocol), got \"tcp\"");
}

}  // namespace
}  // namespace vpe::firmware
