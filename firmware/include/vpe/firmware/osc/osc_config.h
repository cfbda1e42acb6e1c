// SPDX-License-Identifier: MIT
// OscConfig: the board file's [osc] section (boards/README.md, firmware/osc/README.md): whether
// the player listens for OSC, on which local address and UDP port, and from which senders.
#pragma once

#include <string>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

#include "vpe/firmware/osc/source_allow_list.h"

namespace vpe::firmware {

struct OscConfig {
    bool enabled = true;
    // A numeric local address to listen on: "127.0.0.1" (this machine only, the default),
    // "0.0.0.0" (every IPv4 interface), one interface's address, "::1" or "::".
    std::string address = "127.0.0.1";
    // UDP port. The board file takes 1..65535; 0 (an ephemeral port, see OscServer::port) is
    // for tests.
    int port = 9000;
    // The senders whose datagrams are read (`allow = ["192.168.1.0/24", "10.0.0.5"]`); empty
    // (the key absent): every sender that reaches the bound address.
    SourceAllowList allow;
};

// Reads the [osc] table (nullptr: the section is absent, the defaults). Keys: enabled
// (boolean), address (string), port (integer), protocol ("udp", the only one), allow (an array
// of addresses and networks; an empty array is refused as ambiguous). `source` names the file
// in errors. Throws BoardConfigError "file:osc.port: expected 1..65535, got 70000".
OscConfig parseOscConfig(const toml::table* osc, const std::string& source);

}  // namespace vpe::firmware
