// SPDX-License-Identifier: MIT
#include "mosquitto_broker.h"

#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "test_paths.h"

namespace vpe::firmware::bus::testing {

namespace fs = std::filesystem;

namespace {

bool accepts(int port) {
    const int probe = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (probe < 0) {
        return false;
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool connected =
        ::connect(probe, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
    ::close(probe);
    return connected;
}

std::string readAll(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

std::string showAcl() {
    const std::string acl = readAll(fs::path(test_paths::sourceDir()) / "boards/mosquitto/acl");
    if (acl.find("user " + kController.name) == std::string::npos) {
        throw std::runtime_error("boards/mosquitto/acl: no user " + kController.name);
    }
    return acl;
}

std::optional<std::string> MosquittoBroker::unavailable() {
    for (const char* program : {kProgram, kPasswordTool}) {
        if (::access(program, X_OK) != 0) {
            return std::string(program) +
                   " is absent (Debian's mosquitto; scripts/install-deps.sh --test)";
        }
    }
    return std::nullopt;
}

int MosquittoBroker::freePort() {
    const int probe = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (probe < 0 || ::bind(probe, reinterpret_cast<const sockaddr*>(&address), length) != 0 ||
        ::getsockname(probe, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
        throw std::runtime_error("no free TCP port on 127.0.0.1");
    }
    ::close(probe);
    return ntohs(address.sin_port);
}

MosquittoBroker::MosquittoBroker(const fs::path& folder, const std::vector<BrokerUser>& users,
                                 const std::string& acl, int port,
                                 const std::string& listenerOptions)
    : folder_(folder), port_(port == 0 ? freePort() : port) {
    fs::create_directories(folder_);
    const fs::path passwords = folder_ / "passwords";
    std::ofstream(passwords).close();
    for (const BrokerUser& user : users) {
        const std::string command = std::string(kPasswordTool) + " -b '" + passwords.string() +
                                    "' '" + user.name + "' '" + user.password + "' 2>&1";
        if (std::system(command.c_str()) != 0) {
            throw std::runtime_error(command + ": failed");
        }
    }
    std::ofstream(folder_ / "acl") << acl;
    std::ofstream conf(folder_ / "mosquitto.conf");
    // As root mosquitto would switch to the user "mosquitto", who cannot read the test's files.
    if (::geteuid() == 0) {
        conf << "user root\n";
    }
    conf << "listener " << port_ << " 127.0.0.1\n"
         << listenerOptions << "allow_anonymous false\n"
         << "password_file " << passwords.string() << "\n"
         << "acl_file " << (folder_ / "acl").string() << "\n"
         << "persistence true\n"
         << "persistence_location " << folder_.string() << "/\n"
         << "log_dest file " << (folder_ / "mosquitto.log").string() << "\n"
         << "log_type error\nlog_type warning\nlog_type notice\nlog_type information\n";
}

MosquittoBroker::~MosquittoBroker() {
    if (process_.started()) {
        process_.stop(std::chrono::milliseconds(3000));
    }
}

void MosquittoBroker::start() {
    process_ = ChildProcess({kProgram, "-c", (folder_ / "mosquitto.conf").string()},
                            folder_ / "mosquitto.out", folder_ / "mosquitto.err");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (std::chrono::steady_clock::now() < deadline) {
        if (accepts(port_)) {
            return;
        }
        if (!process_.running()) {
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    throw std::runtime_error("mosquitto on port " + std::to_string(port_) +
                             " did not start: " + readAll(folder_ / "mosquitto.err") + log());
}

void MosquittoBroker::stop(int signal) {
    process_.signal(signal);
    process_.wait(std::chrono::milliseconds(5000));
}

BusConfig MosquittoBroker::clientConfig(const BrokerUser& user, BusRole role,
                                        const std::string& clientId) const {
    BusConfig c;
    c.enabled = true;
    c.port = port_;
    c.username = user.name;
    c.password = user.password;
    c.show = "test";
    c.role = role;
    c.clientId = clientId;
    return c;
}

std::string MosquittoBroker::log() const {
    return readAll(folder_ / "mosquitto.log");
}

}  // namespace vpe::firmware::bus::testing
