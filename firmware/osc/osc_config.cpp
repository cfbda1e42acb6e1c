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
    checkKeys(*osc, source, section, {"enabled", "address", "port", "protocol"});
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
    return config;
}

}  // namespace vpe::firmware
