// SPDX-License-Identifier: MIT
#include "vpe/firmware/osc/source_allow_list.h"

#include <charconv>
#include <cstring>

#include <arpa/inet.h>
#include <netinet/in.h>

namespace vpe::firmware {

namespace {

bool prefixMatches(const std::uint8_t* address, const std::uint8_t* network, int bits) {
    const int whole = bits / 8;
    if (std::memcmp(address, network, static_cast<std::size_t>(whole)) != 0) {
        return false;
    }
    const int rest = bits % 8;
    if (rest == 0) {
        return true;
    }
    const auto mask = static_cast<std::uint8_t>(0xff << (8 - rest));
    return (address[whole] & mask) == (network[whole] & mask);
}

// The sender as (IPv6?, 16 bytes), a v4-mapped IPv6 sender as the IPv4 address it is.
std::optional<std::pair<bool, std::array<std::uint8_t, 16>>> senderAddress(
    const sockaddr_storage& sender) {
    std::array<std::uint8_t, 16> bytes{};
    if (sender.ss_family == AF_INET) {
        const auto& v4 = reinterpret_cast<const sockaddr_in&>(sender);
        std::memcpy(bytes.data(), &v4.sin_addr, 4);
        return std::pair{false, bytes};
    }
    if (sender.ss_family == AF_INET6) {
        const auto& v6 = reinterpret_cast<const sockaddr_in6&>(sender);
        if (IN6_IS_ADDR_V4MAPPED(&v6.sin6_addr)) {
            std::memcpy(bytes.data(), v6.sin6_addr.s6_addr + 12, 4);
            return std::pair{false, bytes};
        }
        std::memcpy(bytes.data(), v6.sin6_addr.s6_addr, 16);
        return std::pair{true, bytes};
    }
    return std::nullopt;
}

}  // namespace

std::optional<SourceAllowList::Network> SourceAllowList::parse(const std::string& text,
                                                               std::string& problem) {
    Network network;
    network.text = text;
    const std::size_t slash = text.find('/');
    const std::string address = text.substr(0, slash);
    if (::inet_pton(AF_INET, address.c_str(), network.address.data()) == 1) {
        network.ipv6 = false;
        network.prefixBits = 32;
    } else if (::inet_pton(AF_INET6, address.c_str(), network.address.data()) == 1) {
        network.ipv6 = true;
        network.prefixBits = 128;
    } else {
        problem = "\"" + text +
                  "\": expected an IPv4 or IPv6 address, or a network such as "
                  "\"192.168.1.0/24\"";
        return std::nullopt;
    }
    const int widest = network.prefixBits;
    if (slash != std::string::npos) {
        const std::string bits = text.substr(slash + 1);
        int prefix = -1;
        const auto [end, error] = std::from_chars(bits.data(), bits.data() + bits.size(), prefix);
        if (bits.empty() || error != std::errc{} || end != bits.data() + bits.size() ||
            prefix < 0 || prefix > widest) {
            problem = "\"" + text + "\": the prefix length must be 0.." + std::to_string(widest);
            return std::nullopt;
        }
        network.prefixBits = prefix;
    }
    // Host bits set ("192.168.1.5/24") is most likely a typo for a single address or for the
    // network: say which network it would be rather than guess.
    std::array<std::uint8_t, 16> masked{};
    for (int bit = 0; bit < network.prefixBits; ++bit) {
        const auto byte = static_cast<std::size_t>(bit / 8);
        masked[byte] =
            static_cast<std::uint8_t>(masked[byte] | (network.address[byte] & (0x80 >> (bit % 8))));
    }
    if (masked != network.address) {
        char shown[INET6_ADDRSTRLEN] = {};
        ::inet_ntop(network.ipv6 ? AF_INET6 : AF_INET, masked.data(), shown, sizeof shown);
        problem = "\"" + text + "\": host bits set (the network is " + shown + "/" +
                  std::to_string(network.prefixBits) + ")";
        return std::nullopt;
    }
    return network;
}

bool SourceAllowList::allows(const sockaddr_storage& sender) const {
    if (networks_.empty()) {
        return true;
    }
    const auto address = senderAddress(sender);
    if (!address) {
        return false;
    }
    for (const Network& network : networks_) {
        if (network.ipv6 == address->first &&
            prefixMatches(address->second.data(), network.address.data(), network.prefixBits)) {
            return true;
        }
    }
    return false;
}

std::string SourceAllowList::describe() const {
    std::string text;
    for (const Network& network : networks_) {
        text += (text.empty() ? "" : ", ") + network.text;
    }
    return text;
}

std::string describeSender(const sockaddr_storage& sender) {
    const auto address = senderAddress(sender);
    if (!address) {
        return "an unknown address family";
    }
    char shown[INET6_ADDRSTRLEN] = {};
    ::inet_ntop(address->first ? AF_INET6 : AF_INET, address->second.data(), shown, sizeof shown);
    const std::uint16_t port =
        ntohs(sender.ss_family == AF_INET6 ? reinterpret_cast<const sockaddr_in6&>(sender).sin6_port
                                           : reinterpret_cast<const sockaddr_in&>(sender).sin_port);
    return address->first ? "[" + std::string(shown) + "]:" + std::to_string(port)
                          : std::string(shown) + ":" + std::to_string(port);
}

}  // namespace vpe::firmware
