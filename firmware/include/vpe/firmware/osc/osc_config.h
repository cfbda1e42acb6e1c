// SPDX-License-Identifier: MIT
// OscConfig: the board file's [osc] section (boards/README.md, firmware/osc/README.md): whether
// the player listens for OSC, on which local address and UDP port.
#pragma once

#include <string>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

namespace vpe::firmware {

struct OscConfig {
    bool enabled = true;
    // A numeric local address to listen on: "127.0.0.1" (this machine only, the default),
    // "0.0.0.0" (every IPv4 interface), one interface's address, "::1" or "::".
    std::string address = "127.0.0.1";
    // UDP port. The board file takes 1..65535; 0 (an ephemeral port, see OscServer::port) is
    // for tests.
    int port = 9000;
};

// Reads the [osc] table (nullptr: the section is absent, the defaults). Keys: enabled
// (boolean), address (string), port (integer), protocol ("udp", the only one). `source` names
// the file in errors. Throws BoardConfigError "file:osc.port: expected 1..65535, got 70000".
OscConfig parseOscConfig(const toml::table* osc, const std::string& source);

}  // namespace vpe::firmware
