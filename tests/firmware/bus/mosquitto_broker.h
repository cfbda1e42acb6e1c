// SPDX-License-Identifier: MIT
// MosquittoBroker: a broker of a test's own: mosquitto with a generated configuration (no
// anonymous clients, a password file made with mosquitto_passwd, an ACL, persistence in the
// test's folder) on a free loopback port, stopped when the test ends. The bus tests SKIP
// without /usr/sbin/mosquitto (Debian's mosquitto; mosquitto-clients is not needed).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/firmware/bus/bus_config.h"

#include "child_process.h"

namespace vpe::firmware::bus::testing {

struct BrokerUser {
    std::string name, password;
};

// The users boards/mosquitto/acl names, and that ACL itself (the file shipped, so that the tests
// hold it to its word): controllers may write the light, players only read it.
inline const BrokerUser kController{"vpe-controller", "controller-secret"};
inline const BrokerUser kPlayer{"vpe-player", "player-secret"};
// The control page's watching role (status and light only).
inline const BrokerUser kViewer{"vpe-viewer", "viewer-secret"};
std::string showAcl();

class MosquittoBroker {
public:
    static constexpr const char* kProgram = "/usr/sbin/mosquitto";
    static constexpr const char* kPasswordTool = "/usr/bin/mosquitto_passwd";

    // Empty when the broker can run here; else why not (for GTEST_SKIP).
    static std::optional<std::string> unavailable();
    // A TCP port on 127.0.0.1 that nothing listens on now.
    static int freePort();

    // Writes mosquitto.conf, passwords and acl into `folder` (created). `port` 0: a free one.
    // `listenerOptions`: lines for the listener (cafile, certfile, keyfile: TLS). Throws
    // std::runtime_error when mosquitto_passwd fails.
    MosquittoBroker(const std::filesystem::path& folder, const std::vector<BrokerUser>& users,
                    const std::string& acl, int port = 0, const std::string& listenerOptions = "");
    ~MosquittoBroker();
    MosquittoBroker(const MosquittoBroker&) = delete;
    MosquittoBroker& operator=(const MosquittoBroker&) = delete;

    // Starts mosquitto and waits until it accepts connections (up to 5 s). Throws
    // std::runtime_error with its log when it does not.
    void start();
    // SIGTERM (a clean stop: retained messages saved) or SIGKILL (a crash), and waits.
    void stop(int signal = SIGTERM);
    bool running() { return process_.running(); }

    int port() const { return port_; }
    // A node's [bus] section for this broker: enabled, as user, in the show "test".
    BusConfig clientConfig(const BrokerUser& user, BusRole role, const std::string& clientId) const;
    const std::filesystem::path& folder() const { return folder_; }
    std::string log() const;

private:
    std::filesystem::path folder_;
    int port_;
    ChildProcess process_;
};

}  // namespace vpe::firmware::bus::testing
