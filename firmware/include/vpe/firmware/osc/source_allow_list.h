// SPDX-License-Identifier: MIT
// SourceAllowList: the [osc] allow list (firmware/osc/README.md): the sender addresses whose
// datagrams the OSC server reads, each a single IPv4 or IPv6 address or a CIDR network
// ("192.168.1.0/24", "10.0.0.5", "fd00::/8"). An IPv4 sender reaching a socket bound to "::"
// arrives as ::ffff:a.b.c.d and is matched as the IPv4 address it is. An empty list allows
// every sender (the server's bound address is the only limit, loopback by default).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <sys/socket.h>

namespace vpe::firmware {

class SourceAllowList {
public:
    struct Network {
        bool ipv6 = false;
        std::array<std::uint8_t, 16> address{};  // IPv4 in the first 4 bytes
        int prefixBits = 32;
        std::string text;  // as written
    };

    // One entry: a network, or empty with `problem` saying what is wrong ("host bits set:
    // the network is 192.168.1.0/24").
    static std::optional<Network> parse(const std::string& text, std::string& problem);

    SourceAllowList() = default;  // every sender
    explicit SourceAllowList(std::vector<Network> networks) : networks_(std::move(networks)) {}

    bool allowsEverySender() const { return networks_.empty(); }
    bool allows(const sockaddr_storage& sender) const;
    const std::vector<Network>& networks() const { return networks_; }
    // "192.168.1.0/24, 10.0.0.5"
    std::string describe() const;

private:
    std::vector<Network> networks_;
};

// "192.168.1.7:53000", "[fd00::7]:53000" (a v4-mapped address as IPv4).
std::string describeSender(const sockaddr_storage& sender);

}  // namespace vpe::firmware
