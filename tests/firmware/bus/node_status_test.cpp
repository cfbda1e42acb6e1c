// SPDX-License-Identifier: MIT
// The control page's messages (proto/BUS.md, "Node status", "Blackout"): a node's status as
// JSON, the blackout switch read strictly (every refusal one line, never a throw), and the
// SoC temperature where /sys/class/thermal has it.
#include "vpe/firmware/bus/node_status.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

namespace vpe::firmware::bus {
namespace {

TEST(NodeStatusTest, EncodesEveryField) {
    NodeStatus status;
    status.node = "vpe-foyer-left";
    status.role = "player";
    status.timeUs = 1'718'000'000'123'456;
    status.fps = 59.94;
    status.frameP99Ms = 4.25;
    status.skipped = 3;
    status.socTemperatureC = 51.2;
    status.bundle = "vase.vpeb";
    status.bundleChecksum = "0x1a2b3c4d";
    status.activeInput = "bus";
    status.uptimeS = 3600.5;
    status.watchdog = "systemd 10 s";
    status.light = {20, 35, 0.6};
    status.limits.distanceM = std::pair{0.05, 5.0};
    status.presets = {"stripes", "radial"};
    status.preset = "radial";
    const auto json = nlohmann::json::parse(encodeNodeStatus(status));
    EXPECT_EQ(json["format"], 1);
    EXPECT_EQ(json["node"], "vpe-foyer-left");
    EXPECT_EQ(json["time_us"], 1'718'000'000'123'456);
    EXPECT_DOUBLE_EQ(json["fps"].get<double>(), 59.94);
    EXPECT_DOUBLE_EQ(json["frame_p99_ms"].get<double>(), 4.25);
    EXPECT_EQ(json["skipped"], 3);
    EXPECT_DOUBLE_EQ(json["soc_temp_c"].get<double>(), 51.2);
    EXPECT_EQ(json["bundle_checksum"], "0x1a2b3c4d");
    EXPECT_EQ(json["input"], "bus");
    EXPECT_EQ(json["last_error"], "");
    EXPECT_EQ(json["light"]["elevation"], 35);
    EXPECT_EQ(json["limits"]["distance"][1], 5);
    EXPECT_EQ(json["presets"][1], "radial");
    EXPECT_EQ(json["blackout"], false);
    status.socTemperatureC.reset();
    status.lastError = std::string("bus: \xff bad byte");  // invalid UTF-8 from the network
    const auto absent = nlohmann::json::parse(encodeNodeStatus(status));
    EXPECT_TRUE(absent["soc_temp_c"].is_null());
    EXPECT_FALSE(absent["last_error"].get<std::string>().empty());
}

TEST(NodeStatusTest, BlackoutRoundTrip) {
    const BlackoutMessage sent{"vpe-page-1", 1'718'000'000'000'000, true};
    const auto decoded = decodeBlackoutMessage(encodeBlackoutMessage(sent));
    ASSERT_TRUE(std::holds_alternative<BlackoutMessage>(decoded));
    EXPECT_EQ(std::get<BlackoutMessage>(decoded).node, "vpe-page-1");
    EXPECT_TRUE(std::get<BlackoutMessage>(decoded).on);
}

TEST(NodeStatusTest, BlackoutRefusals) {
    const auto refused = [](const std::string& payload) {
        const auto decoded = decodeBlackoutMessage(payload);
        EXPECT_TRUE(std::holds_alternative<LightMessageRefusal>(decoded)) << payload;
        return std::holds_alternative<LightMessageRefusal>(decoded)
                   ? std::get<LightMessageRefusal>(decoded)
                   : LightMessageRefusal{};
    };
    const std::string time = "\"time_us\":1718000000000000";
    EXPECT_EQ(refused("on").problem, LightMessageProblem::kMalformed);
    EXPECT_EQ(refused("[]").problem, LightMessageProblem::kMalformed);
    EXPECT_EQ(refused("{\"format\":2,\"node\":\"p\"," + time + ",\"on\":true}").reason,
              "\"format\": expected 1");
    EXPECT_EQ(refused("{\"format\":1,\"node\":\"\"," + time + ",\"on\":true}").problem,
              LightMessageProblem::kMalformed);
    EXPECT_EQ(refused("{\"format\":1,\"node\":\"p\"," + time + ",\"on\":1}").reason,
              "\"on\": expected true or false");
    EXPECT_EQ(refused("{\"format\":1,\"node\":\"p\",\"time_us\":1.5,\"on\":true}").problem,
              LightMessageProblem::kMalformed);
    EXPECT_EQ(refused("{\"format\":1,\"node\":\"p\",\"time_us\":1718000000,\"on\":true}").problem,
              LightMessageProblem::kOutOfRange);
    EXPECT_EQ(refused(std::string(5000, ' ')).problem, LightMessageProblem::kMalformed);
}

TEST(NodeStatusTest, SocTemperatureFromThermalZones) {
    const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("vpe-thermal-" + std::to_string(::getpid()));
    EXPECT_FALSE(readSocTemperature(root.string()).has_value());
    std::filesystem::create_directories(root / "thermal_zone0");
    std::ofstream(root / "thermal_zone0" / "temp") << "48312\n";
    const auto celsius = readSocTemperature(root.string());
    ASSERT_TRUE(celsius.has_value());
    EXPECT_DOUBLE_EQ(*celsius, 48.312);
    std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace vpe::firmware::bus
