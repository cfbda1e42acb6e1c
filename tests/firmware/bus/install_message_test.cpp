// SPDX-License-Identifier: MIT
// The control page's install steps on the bus (proto/BUS.md, "Install steps"): the command read
// strictly (every refusal one line, never a throw), the progress as JSON, and against a real
// broker with the shipped ACL: a controller's command reaches the node it names, a malformed one
// is refused and counted, the viewer's is refused by the broker and reaches no node, and the
// node's progress and images arrive retained. SKIPs the broker part without mosquitto.
#include "vpe/firmware/bus/install_message.h"

#include <chrono>
#include <filesystem>
#include <functional>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <poll.h>
#include <unistd.h>

#include "vpe/firmware/bus/light_bus.h"
#include "vpe/firmware/loop/show_clock.h"

#include "mosquitto_broker.h"

namespace vpe::firmware::bus {
namespace {

namespace fs = std::filesystem;
using namespace testing;

constexpr std::int64_t kNow = 1'718'000'000'000'000;
constexpr std::int64_t kMaxAge = 30'000'000;

std::string command(const std::string& fields) {
    return "{\"format\":1,\"node\":\"vpe-page-1\",\"time_us\":" + std::to_string(kNow) + "," +
           fields + "}";
}

LightMessageRefusal refusalOf(const std::string& payload, std::int64_t now = kNow) {
    auto decoded = decodeInstallCommand(payload, now, kMaxAge);
    EXPECT_TRUE(std::holds_alternative<LightMessageRefusal>(decoded)) << payload;
    return std::holds_alternative<LightMessageRefusal>(decoded)
               ? std::get<LightMessageRefusal>(decoded)
               : LightMessageRefusal{};
}

TEST(InstallMessageTest, CommandRoundTrip) {
    for (const InstallAction action : {InstallAction::kScan, InstallAction::kRadiometry}) {
        const InstallCommand sent{"vpe-page-3f2a", kNow - 5, action};
        auto decoded = decodeInstallCommand(encodeInstallCommand(sent), kNow, kMaxAge);
        ASSERT_TRUE(std::holds_alternative<InstallCommand>(decoded));
        const auto& got = std::get<InstallCommand>(decoded);
        EXPECT_EQ(got.node, "vpe-page-3f2a");
        EXPECT_EQ(got.timeUs, kNow - 5);
        EXPECT_EQ(got.action, action);
    }
    EXPECT_EQ(encodeInstallCommand({"p", kNow, InstallAction::kScan}),
              "{\"format\":1,\"node\":\"p\",\"time_us\":" + std::to_string(kNow) +
                  ",\"action\":\"scan\"}");
}

TEST(InstallMessageTest, CommandRefusals) {
    const auto malformed = [](const std::string& payload, const std::string& reason) {
        const LightMessageRefusal refusal = refusalOf(payload);
        EXPECT_EQ(refusal.problem, LightMessageProblem::kMalformed) << payload;
        EXPECT_EQ(refusal.reason, reason) << payload;
        EXPECT_EQ(refusal.reason.find('\n'), std::string::npos);
    };
    malformed("scan please", "not a JSON object");
    malformed("[1]", "not a JSON object");
    malformed("{\"format\":2,\"node\":\"p\",\"time_us\":1,\"action\":\"scan\"}",
              "\"format\": expected 1");
    malformed(command("\"action\":3"), "\"action\": expected \"scan\" or \"radiometry\"");
    malformed(command("\"oops\":1"), "\"action\": expected \"scan\" or \"radiometry\"");
    malformed("{\"format\":1,\"node\":\"\",\"time_us\":1,\"action\":\"scan\"}",
              "\"node\": expected a name of 1-64 bytes");
    malformed("{\"format\":1,\"node\":\"p\",\"time_us\":1.5,\"action\":\"scan\"}",
              "\"time_us\": expected whole microseconds");
    malformed(std::string(5000, ' '), "5000 bytes, more than 4096");

    const auto outOfRange = [](const std::string& payload, std::int64_t now,
                               const std::string& reason) {
        const LightMessageRefusal refusal = refusalOf(payload, now);
        EXPECT_EQ(refusal.problem, LightMessageProblem::kOutOfRange) << payload;
        EXPECT_EQ(refusal.reason, reason) << payload;
    };
    outOfRange(command("\"action\":\"dance\""), kNow,
               "\"action\" \"dance\" is not \"scan\" or \"radiometry\"");
    outOfRange("{\"format\":1,\"node\":\"p\",\"time_us\":1718000000,\"action\":\"scan\"}", kNow,
               "\"time_us\" 1718000000 is not a wall-clock time in microseconds");
    // Held back by the network, or from another clock: no capture.
    outOfRange(command("\"action\":\"scan\""), kNow + 31'000'000,
               "made 31.0 s before this node's clock (a command older than 30 s, or from the "
               "future, runs nothing)");
    outOfRange(command("\"action\":\"scan\""), kNow - 3'000'000,
               "made -3.0 s before this node's clock (a command older than 30 s, or from the "
               "future, runs nothing)");
}

TEST(InstallMessageTest, ProgressJson) {
    InstallProgress progress;
    progress.node = "node-a";
    progress.timeUs = kNow;
    progress.action = InstallAction::kRadiometry;
    progress.requestedBy = "vpe-page-1";
    progress.step = "radiometry: flat-white";
    progress.framesDone = 3;
    progress.framesTotal = 50;
    progress.elapsedS = 1.23456;
    progress.out = "/var/lib/vpe/scan/radiometry";
    const auto json = nlohmann::ordered_json::parse(encodeInstallProgress(progress));
    std::vector<std::string> keys;
    for (const auto& item : json.items()) {
        keys.push_back(item.key());
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"format", "node", "time_us", "action", "requested_by",
                                              "state", "step", "frames_done", "frames_total",
                                              "elapsed_s", "out", "result", "error", "lit_fraction",
                                              "decodable_fraction"}));
    EXPECT_EQ(json["action"], "radiometry");
    EXPECT_EQ(json["state"], "running");
    EXPECT_EQ(json["frames_done"], 3);
    EXPECT_DOUBLE_EQ(json["elapsed_s"].get<double>(), 1.235);
    EXPECT_TRUE(json["lit_fraction"].is_null());
    progress.state = InstallState::kFailed;
    progress.error = "scan: black: …";
    progress.litFraction = 0.5;
    const auto failed = nlohmann::json::parse(encodeInstallProgress(progress));
    EXPECT_EQ(failed["state"], "failed");
    EXPECT_EQ(failed["error"], "scan: black: …");
    EXPECT_DOUBLE_EQ(failed["lit_fraction"].get<double>(), 0.5);
}

// A client of the test's own (the page, steering or watching), driven by hand.
struct Client {
    std::vector<int> acknowledged;  // reason codes
    std::vector<std::pair<std::string, std::string>> received;
    std::unique_ptr<MqttConnection> connection;

    Client(int port, const BrokerUser& user, const std::string& id,
           std::vector<std::string> subscriptions = {}) {
        MqttSettings settings;
        settings.port = port;
        settings.clientId = id;
        settings.username = user.name;
        settings.password = user.password;
        settings.subscriptions = std::move(subscriptions);
        MqttConnection::Handlers handlers;
        handlers.message = [this](std::string_view topic, std::string_view payload, bool) {
            received.emplace_back(std::string(topic), std::string(payload));
        };
        handlers.acknowledged = [this](int, int reason) { acknowledged.push_back(reason); };
        connection = std::make_unique<MqttConnection>(settings, std::move(handlers));
    }
    void turn() { connection->service(monotonicNowNs()); }
};

class InstallBusTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (const auto why = MosquittoBroker::unavailable()) {
            GTEST_SKIP() << *why;
        }
        folder_ = fs::temp_directory_path() / ("vpe-install-bus-" + std::to_string(::getpid()));
        broker_ = std::make_unique<MosquittoBroker>(
            folder_, std::vector{kController, kPlayer, kViewer}, showAcl());
        broker_->start();
    }
    void TearDown() override {
        broker_.reset();
        fs::remove_all(folder_);
    }

    fs::path folder_;
    std::unique_ptr<MosquittoBroker> broker_;
};

TEST_F(InstallBusTest, CommandsProgressAndTheAcl) {
    const BusConfig config = broker_->clientConfig(kPlayer, BusRole::kPlayer, "node-a");
    std::vector<std::string> lines;
    LightLimits limits;
    limits.distanceM = std::pair{0.3, 1.5};
    LightBus node(config, limits, {}, [&lines](const std::string& l) { lines.push_back(l); });
    std::vector<InstallCommand> commands;
    node.onInstallCommand([&commands](const InstallCommand& c) { commands.push_back(c); });
    Client controller(broker_->port(), kController, "vpe-page-c", {"vpe/test/install/node-a/+"});
    Client viewer(broker_->port(), kViewer, "vpe-page-v", {"vpe/test/install/node-a/+"});
    std::vector<InputEvent> events;
    const auto runUntil = [&](const std::function<bool()>& done,
                              std::chrono::milliseconds limit = std::chrono::seconds(3)) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < deadline) {
            pollfd descriptor{node.pollDescriptors().at(0), POLLIN, 0};
            ::poll(&descriptor, 1, 5);
            node.onTick(monotonicNowNs(), events);
            controller.turn();
            viewer.turn();
            if (done()) {
                return true;
            }
        }
        return false;
    };
    ASSERT_TRUE(runUntil([&] {
        return node.connected() && controller.connection->connected() &&
               viewer.connection->connected();
    }));
    // The subscriptions follow the connection: give them the time to be in place (a command is
    // not retained: one sent before would reach nobody, as the page's would).
    runUntil([] { return false; }, std::chrono::milliseconds(300));
    const std::string topic = config.commandTopic();
    EXPECT_EQ(topic, "vpe/test/command/node-a");
    const auto now = [] { return realtimeNowNs() / 1000; };

    // The controller's command reaches the node, once.
    ASSERT_TRUE(controller.connection->publish(
        topic, encodeInstallCommand({"vpe-page-c", now(), InstallAction::kScan}), 1, false));
    ASSERT_TRUE(runUntil([&] { return !commands.empty(); }));
    EXPECT_EQ(commands.at(0).node, "vpe-page-c");
    EXPECT_EQ(commands.at(0).action, InstallAction::kScan);

    // A malformed one is refused: one line, counted.
    ASSERT_TRUE(controller.connection->publish(topic, "{\"format\":1}", 1, false));
    ASSERT_TRUE(runUntil([&] { return node.refusals().count("bus.malformed") > 0; }));
    EXPECT_EQ(node.refusals().at("bus.malformed"), 1u);
    EXPECT_NE(lines.back().find("vpe/test/command/node-a: \"node\": expected a name"),
              std::string::npos)
        << lines.back();

    // The viewer's is refused by the broker (not authorized) and never arrives.
    ASSERT_TRUE(viewer.connection->publish(
        topic, encodeInstallCommand({"vpe-page-v", now(), InstallAction::kRadiometry}), 1, false));
    ASSERT_TRUE(runUntil([&] { return !viewer.acknowledged.empty(); }));
    EXPECT_GE(viewer.acknowledged.at(0), 0x80);
    runUntil([] { return false; }, std::chrono::milliseconds(300));  // time to arrive, if it would
    EXPECT_EQ(commands.size(), 1u);

    // The node's progress and images reach both pages.
    InstallProgress progress;
    progress.timeUs = now();
    progress.framesDone = 26;
    progress.framesTotal = 26;
    progress.state = InstallState::kDone;
    node.publishInstallProgress(progress);
    node.publishInstallImage("camera", std::string("\x89PNG\r\n\x1a\n", 8));
    ASSERT_TRUE(
        runUntil([&] { return controller.received.size() >= 2 && viewer.received.size() >= 2; }));
    for (const Client* page : {&controller, &viewer}) {
        EXPECT_EQ(page->received.at(0).first, "vpe/test/install/node-a/progress");
        EXPECT_EQ(nlohmann::json::parse(page->received.at(0).second)["node"], "node-a");
        EXPECT_EQ(page->received.at(1).first, "vpe/test/install/node-a/camera");
        EXPECT_EQ(page->received.at(1).second.size(), 8u);
    }
}

}  // namespace
}  // namespace vpe::firmware::bus
