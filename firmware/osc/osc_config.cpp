// SPDX-License-Identifier: MIT
// OscConfig: the [osc] section, read strictly with the shared board-file helpers.
#include "vpe/firmware/osc/osc_config.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include "board/toml_fields.h"

namespace vpe::firmware {

namespace {

// A numeric IPv4 or IPv6 address: a host name would need a resolver at boot, before the
// network may be up, and could resolve to an address the board does not have.
bool isNumericAddress(const std::string& address) {
    in6_addr storage{};
    return ::inet_pton(AF_INET, address.c_str(), &storage) == 1 ||
           ::inet_pton(AF_INET6, address.c_str(), &storage) == 1;
}

}  // namespace

OscConfig parseOscConfig(const toml::table* osc, const std::string& source) {
    using namespace toml_fields;
    OscConfig config;
    if (osc == nullptr) {
        return config;
    }
    const std::string section = "osc";
    checkKeys(*osc, source, section, {"enabled", "address", "port", "protocol", "allow"});
    config.enabled = optionalBool(*osc, source, section, "enabled").value_or(config.enabled);
    if (const auto address = optionalString(*osc, source, section, "address")) {
        if (!isNumericAddress(*address)) {
            fail(source, qualified(section, "address"),
                 "expected a numeric IPv4 or IPv6 address (\"127.0.0.1\", \"0.0.0.0\", \"::1\"), "
                 "got \"" +
                     *address + "\"");
        }
        config.address = *address;
    }
    if (const auto port = optionalInteger(*osc, source, section, "port")) {
        if (*port < 1 || *port > 65535) {
            fail(source, qualified(section, "port"),
                 "expected 1..65535, got " + std::to_string(*port));
        }
        config.port = static_cast<int>(*port);
    }
    if (const auto protocol = optionalString(*osc, source, section, "protocol")) {
        if (*protocol != "udp") {
            fail(source, qualified(section, "protocol"),
                 "expected \"udp\" (the only protocol), got \"" + *protocol + "\"");
        }
    }
    if (const toml::node* allow = osc->get("allow")) {
        const toml::array* entries = allow->as_array();
        if (entries == nullptr) {
            fail(source, qualified(section, "allow"),
                 std::string("expected an array of addresses, got ") + typeName(*allow));
        }
        if (entries->empty()) {
            // An empty list could mean "nobody" or "anybody": neither is guessed.
            fail(source, qualified(section, "allow"),
                 "empty; leave the key out to take datagrams from every sender, or set "
                 "osc.enabled = false");
        }
        std::vector<SourceAllowList::Network> networks;
        for (std::size_t i = 0; i < entries->size(); ++i) {
            const std::string key = "allow[" + std::to_string(i) + "]";
            const auto* text = (*entries)[i].as_string();
            if (text == nullptr) {
                fail(source, qualified(section, key),
                     std::string("expected a string, got ") + typeName((*entries)[i]));
            }
            std::string problem;
            auto network = SourceAllowList::parse(text->get(), problem);
            if (!network) {
                fail(source, qualified(section, key), problem);
            }
            networks.push_back(std::move(*network));
        }
        config.allow = SourceAllowList(std::move(networks));
    }
    return config;
}

}  // namespace vpe::firmware
