// SPDX-License-Identifier: MIT
// BusConfig: the [bus] section, read strictly with the shared board-file helpers.
#include "vpe/firmware/bus/bus_config.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <unistd.h>

#include "board/toml_fields.h"

namespace vpe::firmware::bus {

namespace {

using namespace toml_fields;

const std::string kSection = "bus";

// A numeric IPv4 or IPv6 address: a host name would need a resolver, which blocks the frame
// loop the client runs in (up to its timeouts) whenever the network is down.
bool isNumericAddress(const std::string& address) {
    in6_addr storage{};
    return ::inet_pton(AF_INET, address.c_str(), &storage) == 1 ||
           ::inet_pton(AF_INET6, address.c_str(), &storage) == 1;
}

// MQTT topic levels and client ids must not hold '/', '+', '#' or controls; keep to a portable
// set that every broker's ACL file can name.
bool isPlainName(const std::string& name, bool allowDot) {
    return !name.empty() && name.size() <= 64 &&
           std::all_of(name.begin(), name.end(), [allowDot](char c) {
               return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '-' || c == '_' || (allowDot && c == '.');
           });
}

std::string defaultClientId() {
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0) {
        return "vpe-player";
    }
    std::string id = "vpe-";
    for (const char* c = host; *c != '\0' && id.size() < 64; ++c) {
        const bool plain = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
                           (*c >= '0' && *c <= '9') || *c == '-' || *c == '_' || *c == '.';
        id += plain ? *c : '-';
    }
    return id;
}

std::filesystem::path nextToBoard(const std::string& source, const std::string& value) {
    const std::filesystem::path path(value);
    return path.is_absolute()
               ? path
               : (std::filesystem::path(source).parent_path() / path).lexically_normal();
}

std::optional<std::filesystem::path> existingFile(const toml::table& bus, const std::string& source,
                                                  const char* key) {
    const auto value = optionalString(bus, source, kSection, key);
    if (!value) {
        return std::nullopt;
    }
    if (value->empty()) {
        fail(source, qualified(kSection, key), "expected a file, got \"\"");
    }
    const std::filesystem::path path = nextToBoard(source, *value);
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        fail(source, qualified(kSection, key), path.string() + ": no such file");
    }
    return path;
}

std::string readPasswordFile(const std::string& source, const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        fail(source, qualified(kSection, "password_file"),
             path.string() + ": cannot read (" + std::strerror(errno) + ")");
    }
    std::string password;
    std::getline(in, password);
    if (!password.empty() && password.back() == '\r') {
        password.pop_back();
    }
    if (password.empty()) {
        fail(source, qualified(kSection, "password_file"),
             path.string() + ": the first line (the password) is empty");
    }
    return password;
}

}  // namespace

const char* busRoleName(BusRole role) {
    return role == BusRole::kController ? "controller" : "player";
}

BusConfig parseBusConfig(const toml::table* bus, const std::string& source) {
    BusConfig config;
    if (bus == nullptr) {
        return config;
    }
    checkKeys(*bus, source, kSection,
              {"enabled", "host", "port", "username", "password", "password_file", "show", "role",
               "cafile", "certfile", "keyfile", "client_id"});
    config.enabled = optionalBool(*bus, source, kSection, "enabled").value_or(true);
    if (const auto host = optionalString(*bus, source, kSection, "host")) {
        if (!isNumericAddress(*host)) {
            fail(source, qualified(kSection, "host"),
                 "expected the broker's numeric IPv4 or IPv6 address (\"192.168.1.10\", "
                 "\"127.0.0.1\", \"::1\"), got \"" +
                     *host + "\"");
        }
        config.host = *host;
    }
    if (const auto username = optionalString(*bus, source, kSection, "username")) {
        if (username->empty()) {
            fail(source, qualified(kSection, "username"), "expected a name, got \"\"");
        }
        config.username = *username;
    }
    const auto password = optionalString(*bus, source, kSection, "password");
    const auto passwordFile = optionalString(*bus, source, kSection, "password_file");
    if (password && passwordFile) {
        fail(source, qualified(kSection, "password_file"),
             "give the password or the password file, not both");
    }
    if ((password || passwordFile) && config.username.empty()) {
        fail(source, qualified(kSection, password ? "password" : "password_file"),
             "a password needs bus.username");
    }
    if (password) {
        if (password->empty()) {
            fail(source, qualified(kSection, "password"), "expected a password, got \"\"");
        }
        config.password = *password;
    } else if (passwordFile) {
        config.password = readPasswordFile(source, nextToBoard(source, *passwordFile));
    }
    if (const auto show = optionalString(*bus, source, kSection, "show")) {
        if (!isPlainName(*show, false)) {
            fail(source, qualified(kSection, "show"),
                 "expected 1 to 64 letters, digits, '-' or '_' (the topic vpe/<show>/light), "
                 "got \"" +
                     *show + "\"");
        }
        config.show = *show;
    } else if (config.enabled) {
        fail(source, qualified(kSection, "show"),
             "missing (the show's name: its nodes share the topic vpe/<show>/light)");
    }
    if (const auto role = optionalString(*bus, source, kSection, "role")) {
        if (*role == "controller") {
            config.role = BusRole::kController;
        } else if (*role != "player") {
            fail(source, qualified(kSection, "role"),
                 "expected \"player\" or \"controller\", got \"" + *role + "\"");
        }
    }
    config.cafile = existingFile(*bus, source, "cafile");
    config.certfile = existingFile(*bus, source, "certfile");
    config.keyfile = existingFile(*bus, source, "keyfile");
    if (config.certfile.has_value() != config.keyfile.has_value()) {
        fail(source, qualified(kSection, config.certfile ? "keyfile" : "certfile"),
             "missing: a client certificate needs both bus.certfile and bus.keyfile");
    }
    if (config.certfile && !config.cafile) {
        fail(source, qualified(kSection, "cafile"),
             "missing: a client certificate is for TLS, which needs the broker's CA (cafile)");
    }
    config.port = config.tls() ? 8883 : 1883;
    if (const auto port = optionalInteger(*bus, source, kSection, "port")) {
        if (*port < 1 || *port > 65535) {
            fail(source, qualified(kSection, "port"),
                 "expected 1..65535, got " + std::to_string(*port));
        }
        config.port = static_cast<int>(*port);
    }
    if (const auto id = optionalString(*bus, source, kSection, "client_id")) {
        if (!isPlainName(*id, true)) {
            fail(source, qualified(kSection, "client_id"),
                 "expected 1 to 64 letters, digits, '-', '_' or '.', got \"" + *id + "\"");
        }
        config.clientId = *id;
    } else {
        config.clientId = defaultClientId();
    }
    return config;
}

}  // namespace vpe::firmware::bus
