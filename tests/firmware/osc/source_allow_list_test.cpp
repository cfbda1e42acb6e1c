// SPDX-License-Identifier: MIT
// SourceAllowList: which senders an [osc] allow list admits: single addresses and CIDR networks,
// IPv4 and IPv6, v4-mapped senders as IPv4, and the entries it refuses with one reason.
#include "vpe/firmware/osc/source_allow_list.h"

#include <cstring>

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>

namespace vpe::firmware {
namespace {

sockaddr_storage sender(const std::string& address, std::uint16_t port = 5000) {
    sockaddr_storage storage{};
    if (address.find(':') == std::string::npos) {
        auto& v4 = reinterpret_cast<sockaddr_in&>(storage);
        v4.sin_family = AF_INET;
        v4.sin_port = htons(port);
        EXPECT_EQ(::inet_pton(AF_INET, address.c_str(), &v4.sin_addr), 1) << address;
    } else {
        auto& v6 = reinterpret_cast<sockaddr_in6&>(storage);
        v6.sin6_family = AF_INET6;
        v6.sin6_port = htons(port);
        EXPECT_EQ(::inet_pton(AF_INET6, address.c_str(), &v6.sin6_addr), 1) << address;
    }
    return storage;
}

SourceAllowList listOf(const std::vector<std::string>& entries) {
    std::vector<SourceAllowList::Network> networks;
    for (const std::string& entry : entries) {
        std::string problem;
        auto network = SourceAllowList::parse(entry, problem);
        EXPECT_TRUE(network.has_value()) << entry << ": " << problem;
        networks.push_back(*network);
    }
    return SourceAllowList(networks);
}

TEST(SourceAllowListTest, AdmitsListedAddressesAndNetworksOnly) {
    const SourceAllowList list = listOf({"192.168.1.0/24", "10.0.0.5", "fd00:1::/32", "::1"});
    for (const char* inside :
         {"192.168.1.0", "192.168.1.77", "192.168.1.255", "10.0.0.5", "fd00:1::7", "fd00:1:ffff::1",
          "::1", "::ffff:192.168.1.9", "::ffff:10.0.0.5"}) {
        EXPECT_TRUE(list.allows(sender(inside))) << inside;
    }
    for (const char* outside : {"192.168.2.1", "10.0.0.6", "10.0.0.4", "127.0.0.1", "fd00:2::1",
                                "::2", "::ffff:10.0.0.6", "0.0.0.0"}) {
        EXPECT_FALSE(list.allows(sender(outside))) << outside;
    }
    // An empty list admits everyone; a /0 network admits its whole family.
    EXPECT_TRUE(SourceAllowList().allows(sender("203.0.113.9")));
    EXPECT_TRUE(listOf({"0.0.0.0/0"}).allows(sender("203.0.113.9")));
    EXPECT_FALSE(listOf({"0.0.0.0/0"}).allows(sender("2001:db8::1")));
    EXPECT_TRUE(listOf({"::/0"}).allows(sender("2001:db8::1")));
    // Prefixes that do not fall on a byte.
    EXPECT_TRUE(listOf({"172.16.0.0/12"}).allows(sender("172.31.255.1")));
    EXPECT_FALSE(listOf({"172.16.0.0/12"}).allows(sender("172.32.0.1")));
}

TEST(SourceAllowListTest, RefusesEntriesWithOneReason) {
    const auto problemOf = [](const std::string& text) {
        std::string problem;
        EXPECT_FALSE(SourceAllowList::parse(text, problem).has_value()) << text;
        return problem;
    };
    EXPECT_EQ(problemOf("10.0.0.1/8"), "\"10.0.0.1/8\": host bits set (the network is 10.0.0.0/8)");
    EXPECT_EQ(problemOf("fd00::1/16"), "\"fd00::1/16\": host bits set (the network is fd00::/16)");
    EXPECT_EQ(problemOf("10.0.0.0/x"), "\"10.0.0.0/x\": the prefix length must be 0..32");
    EXPECT_EQ(problemOf("10.0.0.0/-1"), "\"10.0.0.0/-1\": the prefix length must be 0..32");
    EXPECT_EQ(problemOf("10.0.0"),
              "\"10.0.0\": expected an IPv4 or IPv6 address, or a network "
              "such as \"192.168.1.0/24\"");
    EXPECT_EQ(problemOf(""),
              "\"\": expected an IPv4 or IPv6 address, or a network such as "
              "\"192.168.1.0/24\"");
}

TEST(SourceAllowListTest, NamesSendersForTheLog) {
    EXPECT_EQ(describeSender(sender("192.168.1.7", 53000)), "192.168.1.7:53000");
    EXPECT_EQ(describeSender(sender("fd00::7", 9)), "[fd00::7]:9");
    EXPECT_EQ(describeSender(sender("::ffff:10.0.0.5", 80)), "10.0.0.5:80");
}

}  // namespace
}  // namespace vpe::firmware
