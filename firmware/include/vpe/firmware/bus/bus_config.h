// SPDX-License-Identifier: MIT
// BusConfig: the board file's [bus] section (boards/README.md, docs/multi-node.md): the MQTT
// broker the nodes of one show share their light through, this node's name and credentials,
// and its role: a controller publishes what its own inputs do, a player only follows.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

namespace vpe::firmware::bus {

enum class BusRole { kPlayer, kController };

// "player", "controller".
const char* busRoleName(BusRole role);

struct BusConfig {
    bool enabled = false;
    // The broker: a numeric address (no resolver at boot, as for [osc]; a TLS certificate must
    // then name the address, docs/multi-node.md) and port (1883, or 8883 with TLS).
    std::string host = "127.0.0.1";
    int port = 1883;
    std::string username;  // empty: connect without credentials
    std::string password;  // from `password`, or the first line of `password_file`
    std::string show;      // the topic vpe/<show>/light
    BusRole role = BusRole::kPlayer;
    // TLS when cafile is set (the broker's CA); a client certificate is optional.
    std::optional<std::filesystem::path> cafile, certfile, keyfile;
    // This node's MQTT client id and its name in the messages; unique per broker (a second
    // client with the same id takes the first one's session over). Default "vpe-<hostname>".
    std::string clientId;

    bool tls() const { return cafile.has_value(); }
    // "vpe/<show>/light"
    std::string topic() const { return "vpe/" + show + "/light"; }
    // "vpe/<show>/status/<client id>": this node's status, once a second (proto/BUS.md).
    std::string statusTopic() const { return "vpe/" + show + "/status/" + clientId; }
    // "vpe/<show>/blackout": the control page's blackout switch, followed by every node.
    std::string blackoutTopic() const { return "vpe/" + show + "/blackout"; }
    // "vpe/<show>/command/<client id>": a controller asks this node for a scan or a
    // radiometric capture (the control page's install steps).
    std::string commandTopic() const { return "vpe/" + show + "/command/" + clientId; }
    // "vpe/<show>/install/<client id>/<what>": the capture's progress, camera and coverage.
    std::string installTopic(const std::string& what) const {
        return "vpe/" + show + "/install/" + clientId + "/" + what;
    }
};

// Reads the [bus] table (nullptr: the section is absent, the bus is off). Paths are relative to
// the board file; password_file is read here. Keys: enabled, host, port, username, password,
// password_file, show, role, cafile, certfile, keyfile, client_id. Throws BoardConfigError
// "file:bus.role: expected \"player\" or \"controller\", got \"boss\"".
BusConfig parseBusConfig(const toml::table* bus, const std::string& source);

}  // namespace vpe::firmware::bus
