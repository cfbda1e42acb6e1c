// SPDX-License-Identifier: MIT
// OscConfig: the [osc] section's defaults, values, and one-line refusals naming file:osc.key.
#include "vpe/firmware/osc/osc_config.h"

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

#include "../../support/thrown_message.h"

namespace vpe::firmware {
namespace {

OscConfig parse(const std::string& text) {
    const toml::table root = toml::parse(text);
    return parseOscConfig(root["osc"].as_table(), "board.toml");
}

std::string errorOf(const std::string& text) {
    return vpe::testing::thrownMessage<BoardConfigError>([&] { parse(text); });
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
              "board.toml:osc.host: unknown key (known: address, allow, enabled, port, protocol)");
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

TEST(OscConfigTest, ReadsTheAllowList) {
    EXPECT_TRUE(parse("[osc]\n").allow.allowsEverySender());
    const OscConfig config =
        parse("[osc]\nallow = [\"192.168.1.0/24\", \"10.0.0.5\", \"fd00::/8\", \"::1\"]\n");
    ASSERT_EQ(config.allow.networks().size(), 4u);
    EXPECT_EQ(config.allow.describe(), "192.168.1.0/24, 10.0.0.5, fd00::/8, ::1");
    EXPECT_EQ(config.allow.networks()[1].prefixBits, 32);
    EXPECT_EQ(config.allow.networks()[3].prefixBits, 128);
    EXPECT_EQ(errorOf("[osc]\nallow = []\n"),
              "board.toml:osc.allow: empty; leave the key out to take datagrams from every "
              "sender, or set osc.enabled = false");
    EXPECT_EQ(errorOf("[osc]\nallow = \"10.0.0.5\"\n"),
              "board.toml:osc.allow: expected an array of addresses, got a string");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"10.0.0.5\", 7]\n"),
              "board.toml:osc.allow[1]: expected a string, got an integer");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"gallery.local\"]\n"),
              "board.toml:osc.allow[0]: \"gallery.local\": expected an IPv4 or IPv6 address, or "
              "a network such as \"192.168.1.0/24\"");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"192.168.1.5/24\"]\n"),
              "board.toml:osc.allow[0]: \"192.168.1.5/24\": host bits set (the network is "
              "192.168.1.0/24)");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"10.0.0.0/33\"]\n"),
              "board.toml:osc.allow[0]: \"10.0.0.0/33\": the prefix length must be 0..32");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"fd00::/129\"]\n"),
              "board.toml:osc.allow[0]: \"fd00::/129\": the prefix length must be 0..128");
    EXPECT_EQ(errorOf("[osc]\nallow = [\"10.0.0.0/\"]\n"),
              "board.toml:osc.allow[0]: \"10.0.0.0/\": the prefix length must be 0..32");
}

}  // namespace
}  // namespace vpe::firmware
