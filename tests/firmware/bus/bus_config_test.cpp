// SPDX-License-Identifier: MIT
// BusConfig: the [bus] section's defaults, every key, paths next to the board file, and the
// one-line refusals naming file:bus.key.
#include "vpe/firmware/bus/bus_config.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <toml++/toml.h>
#include <unistd.h>

#include "vpe/firmware/board/board_config.h"

namespace vpe::firmware::bus {
namespace {

namespace fs = std::filesystem;

class BusConfigTest : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = fs::temp_directory_path() / ("vpe-bus-config-" + std::to_string(::getpid()));
        fs::create_directories(folder_);
        board_ = (folder_ / "board.toml").string();
    }
    void TearDown() override { fs::remove_all(folder_); }

    BusConfig parse(const std::string& text) const {
        const toml::table root = toml::parse(text);
        return parseBusConfig(root["bus"].as_table(), board_);
    }
    std::string errorOf(const std::string& text) const {
        try {
            parse(text);
        } catch (const BoardConfigError& error) {
            const std::string what = error.what();
            // Relative to the board, for readable expectations.
            return what.substr(0, board_.size()) == board_
                       ? "board.toml" + what.substr(board_.size())
                       : what;
        }
        return "(no error)";
    }

    // Each text refused with exactly its one line.
    void expectRefusals(const std::vector<std::pair<std::string, std::string>>& refusals) const {
        for (const auto& [text, refusal] : refusals) {
            EXPECT_EQ(errorOf(text), refusal) << text;
        }
    }

    fs::path folder_;
    std::string board_;
};

TEST_F(BusConfigTest, IsOffWithoutASectionAndOnWithOne) {
    const BusConfig absent = parseBusConfig(nullptr, board_);
    EXPECT_FALSE(absent.enabled);
    const BusConfig config = parse("[bus]\nshow = \"foyer\"\n");
    EXPECT_TRUE(config.enabled);
    EXPECT_EQ(config.host, "127.0.0.1");
    EXPECT_EQ(config.port, 1883);
    EXPECT_EQ(config.role, BusRole::kPlayer);  // a node steers the show only when told to
    EXPECT_EQ(config.topic(), "vpe/foyer/light");
    EXPECT_EQ(config.clientId.substr(0, 4), "vpe-");
    EXPECT_TRUE(config.username.empty());
    EXPECT_FALSE(config.tls());
    EXPECT_FALSE(parse("[bus]\nenabled = false\n").enabled);  // no show needed then
}

TEST_F(BusConfigTest, ReadsEveryKey) {
    std::ofstream(folder_ / "password") << "s3cret\nignored\n";
    std::ofstream(folder_ / "ca.crt") << "-----BEGIN CERTIFICATE-----\n";
    std::ofstream(folder_ / "node.crt") << "x";
    std::ofstream(folder_ / "node.key") << "x";
    const BusConfig config = parse(
        "[bus]\nenabled = true\nhost = \"192.168.1.10\"\nusername = \"vpe-controller\"\n"
        "password_file = \"password\"\nshow = \"hall-2\"\nrole = \"controller\"\n"
        "cafile = \"ca.crt\"\ncertfile = \"node.crt\"\nkeyfile = \"node.key\"\n"
        "client_id = \"pi-left.1\"\n");
    EXPECT_EQ(config.host, "192.168.1.10");
    EXPECT_EQ(config.port, 8883);  // TLS's port unless told
    EXPECT_EQ(config.username, "vpe-controller");
    EXPECT_EQ(config.password, "s3cret");
    EXPECT_EQ(config.show, "hall-2");
    EXPECT_EQ(config.role, BusRole::kController);
    EXPECT_EQ(*config.cafile, folder_ / "ca.crt");
    EXPECT_EQ(*config.keyfile, folder_ / "node.key");
    EXPECT_EQ(config.clientId, "pi-left.1");
    EXPECT_EQ(parse("[bus]\nshow = \"s\"\nhost = \"::1\"\nport = 1884\nusername = \"u\"\n"
                    "password = \"p\"\n")
                  .port,
              1884);
}

TEST_F(BusConfigTest, RefusesBadValuesWithOneLine) {
    const std::string show = "[bus]\nshow = \"s\"\n";
    // A password file with an empty first line; a certificate without its key.
    std::ofstream(folder_ / "empty") << "\n";
    std::ofstream(folder_ / "node.crt") << "x";
    EXPECT_EQ(errorOf("[bus]\nbroker = \"x\"\n").substr(0, 36),
              "board.toml:bus.broker: unknown key (");
    expectRefusals({
        {"[bus]\n",
         "board.toml:bus.show: missing (the show's name: its nodes share the topic "
         "vpe/<show>/light)"},
        {"[bus]\nshow = \"a/b\"\n",
         "board.toml:bus.show: expected 1 to 64 letters, digits, '-' or '_' (the topic "
         "vpe/<show>/light), got \"a/b\""},
        {show + "host = \"broker.local\"\n",
         "board.toml:bus.host: expected the broker's numeric IPv4 or IPv6 address "
         "(\"192.168.1.10\", \"127.0.0.1\", \"::1\"), got \"broker.local\""},
        {show + "port = 0\n", "board.toml:bus.port: expected 1..65535, got 0"},
        {show + "role = \"boss\"\n",
         "board.toml:bus.role: expected \"player\" or \"controller\", got \"boss\""},
        {show + "password = \"p\"\n", "board.toml:bus.password: a password needs bus.username"},
        {show + "username = \"u\"\npassword = \"p\"\npassword_file = \"f\"\n",
         "board.toml:bus.password_file: give the password or the password file, not both"},
        {show + "username = \"u\"\npassword_file = \"nowhere\"\n",
         "board.toml:bus.password_file: " + (folder_ / "nowhere").string() +
             ": cannot read (No such file or directory)"},
        {show + "username = \"u\"\npassword_file = \"empty\"\n",
         "board.toml:bus.password_file: " + (folder_ / "empty").string() +
             ": the first line (the password) is empty"},
        {show + "cafile = \"ca.crt\"\n",
         "board.toml:bus.cafile: " + (folder_ / "ca.crt").string() + ": no such file"},
        {show + "certfile = \"node.crt\"\n",
         "board.toml:bus.keyfile: missing: a client certificate needs both bus.certfile "
         "and bus.keyfile"},
        {show + "client_id = \"a b\"\n",
         "board.toml:bus.client_id: expected 1 to 64 letters, digits, '-', '_' or '.', got "
         "\"a b\""},
        {show + "enabled = 1\n", "board.toml:bus.enabled: expected a boolean, got an integer"},
    });
}

}  // namespace
}  // namespace vpe::firmware::bus
