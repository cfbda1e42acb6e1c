// SPDX-License-Identifier: MIT
// LightBus against a real broker of the test's own (mosquitto, generated password file and
// ACL): a state goes round and a node that comes later takes the retained one; the ACL keeps a
// player's user from steering; wrong credentials and an absent broker are one line each and
// the bus reconnects by itself; malformed and out-of-range messages are refused and counted.
// SKIPs without /usr/sbin/mosquitto.
#include "vpe/firmware/bus/light_bus.h"

#include <chrono>
#include <fstream>
#include <functional>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <poll.h>
#include <unistd.h>

#include "vpe/firmware/loop/show_clock.h"

#include "bus_test_limits.h"
#include "mosquitto_broker.h"

namespace vpe::firmware::bus {
namespace {

namespace fs = std::filesystem;
using namespace testing;

constexpr std::int64_t kMs = 1'000'000;

LightLimits limits() {
    return testing::busTestLimits();
}

// A node's bus and what it logged and received.
struct Node {
    std::vector<std::string> lines;
    std::vector<InputEvent> events;
    std::unique_ptr<LightBus> bus;

    Node(const BusConfig& config) {
        bus = std::make_unique<LightBus>(
            config, limits(), std::vector<std::string>{"stripes", "radial"},
            [this](const std::string& line) { lines.push_back(line); });
    }
    // The player's loop, reduced: wait on the descriptor up to 10 ms, serve it, tick.
    void turn() {
        pollfd descriptor{bus->pollDescriptors().at(0), POLLIN, 0};
        if (::poll(&descriptor, 1, 10) > 0) {
            bus->onReadable(descriptor.fd, monotonicNowNs(), events);
        }
        bus->onTick(monotonicNowNs(), events);
    }
    std::size_t linesWith(const std::string& needle) const {
        return static_cast<std::size_t>(std::count_if(
            lines.begin(), lines.end(),
            [&](const std::string& l) { return l.find(needle) != std::string::npos; }));
    }
};

// Turns every node's loop until `done` or the time is up.
bool runUntil(std::vector<Node*> nodes, const std::function<bool()>& done,
              std::chrono::milliseconds limit = std::chrono::milliseconds(3000)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
        for (Node* node : nodes) {
            node->turn();
        }
        if (done()) {
            return true;
        }
    }
    return false;
}

class LightBusTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (const auto why = MosquittoBroker::unavailable()) {
            GTEST_SKIP() << *why;
        }
        folder_ = fs::temp_directory_path() /
                  ("vpe-light-bus-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
        broker_ = std::make_unique<MosquittoBroker>(folder_, std::vector{kController, kPlayer},
                                                    showAcl());
    }
    void TearDown() override {
        broker_.reset();
        fs::remove_all(folder_);
    }

    BusConfig config(const BrokerUser& user, BusRole role, const std::string& id) const {
        return broker_->clientConfig(user, role, id);
    }

    static SharedLight someState() {
        SharedLight state;
        const std::int64_t now = realtimeNowNs() / 1000 * 1000;  // whole microseconds
        state.from = {10, 30, 0.6};
        state.target = {-42.5, 55, 0.8};
        state.moveStartNs = now - 20 * kMs;
        state.driftAtNs = now + 30'000 * kMs;
        state.preset = 1;
        state.revisionNs = now;
        state.steeredBy = InputSource::kKnobs;
        return state;
    }

    fs::path folder_;
    std::unique_ptr<MosquittoBroker> broker_;
};

TEST_F(LightBusTest, SharesTheStateAndALateNodeTakesTheRetainedOne) {
    broker_->start();
    Node controller(config(kController, BusRole::kController, "node-a"));
    Node player(config(kPlayer, BusRole::kPlayer, "node-b"));
    ASSERT_TRUE(runUntil({&controller, &player}, [&] {
        return controller.bus->connected() && player.bus->connected();
    })) << broker_->log();
    EXPECT_EQ(controller.bus->description(),
              "bus (mqtt://127.0.0.1:" + std::to_string(broker_->port()) +
                  ", show \"test\", controller \"node-a\")");
    EXPECT_EQ(controller.linesWith("bus: connected to mqtt://127.0.0.1:"), 1u);

    const SharedLight state = someState();
    controller.bus->offer(state, monotonicNowNs());
    ASSERT_TRUE(runUntil({&controller, &player}, [&] {
        return !player.events.empty() && controller.bus->counters().at("bus.published") == 1;
    }));
    const auto check = [&](const InputEvent& event) {
        EXPECT_EQ(event.source, InputSource::kBus);
        const SharedLight& got = std::get<FollowLight>(event.action).state;
        EXPECT_EQ(got.target.azimuthDeg, -42.5);
        EXPECT_EQ(got.target.elevationDeg, 55);
        EXPECT_EQ(got.from.azimuthDeg, 10);
        EXPECT_EQ(got.moveStartNs, state.moveStartNs);
        EXPECT_EQ(got.driftAtNs, state.driftAtNs);
        EXPECT_EQ(got.revisionNs, state.revisionNs);
        EXPECT_EQ(got.preset, 1);  // "radial", by name
    };
    check(player.events.at(0));
    EXPECT_TRUE(controller.events.empty());  // no echo of its own state

    // A node started (or restarted) later takes the retained state as soon as it connects.
    Node late(config(kPlayer, BusRole::kPlayer, "node-c"));
    ASSERT_TRUE(runUntil({&late}, [&] { return !late.events.empty(); })) << broker_->log();
    check(late.events.at(0));

    // The newest of many offered states always goes out last; no more than 60 a second.
    const auto before = std::chrono::steady_clock::now();
    SharedLight newest = state;
    for (int i = 1; i <= 200; ++i) {
        newest.target.azimuthDeg = -42.5 + i * 0.1;
        newest.revisionNs = state.revisionNs + i * kMs;
        controller.bus->offer(newest, monotonicNowNs());
        controller.turn();
    }
    ASSERT_TRUE(runUntil({&controller, &player}, [&] {
        const auto& last = std::get<FollowLight>(player.events.back().action).state;
        return last.revisionNs == newest.revisionNs;
    }));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
    const auto published = controller.bus->counters().at("bus.published");
    EXPECT_LE(static_cast<double>(published - 1), 60.0 * seconds + 2) << seconds << " s";
    EXPECT_LT(published, 150u);  // superseded states were not sent
}

TEST_F(LightBusTest, APlayersUserCannotSteerTheShow) {
    broker_->start();
    // A board that says controller with a player's credentials: the broker's ACL refuses.
    Node impostor(config(kPlayer, BusRole::kController, "node-x"));
    Node listener(config(kPlayer, BusRole::kPlayer, "node-b"));
    ASSERT_TRUE(runUntil({&impostor, &listener},
                         [&] { return impostor.bus->connected() && listener.bus->connected(); }));
    impostor.bus->offer(someState(), monotonicNowNs());
    ASSERT_TRUE(runUntil({&impostor, &listener},
                         [&] { return impostor.bus->counters().at("bus.publish_refused") == 1; }));
    EXPECT_EQ(impostor.linesWith("bus: the broker refused this node's state on vpe/test/light "
                                 "(reason 135): user \"vpe-player\" may not steer the show"),
              1u)
        << ::testing::PrintToString(impostor.lines);
    runUntil(
        {&impostor, &listener}, [] { return false; }, std::chrono::milliseconds(300));
    EXPECT_TRUE(listener.events.empty());
    EXPECT_EQ(impostor.bus->counters().at("bus.published"), 0u);

    // A player role never tries: one line says so.
    Node player(config(kPlayer, BusRole::kPlayer, "node-p"));
    player.bus->offer(someState(), monotonicNowNs());
    player.bus->offer(someState(), monotonicNowNs());
    EXPECT_EQ(player.linesWith("bus: role player: this node's own inputs steer its light only"),
              1u);
}

TEST_F(LightBusTest, WrongCredentialsAreOneLine) {
    broker_->start();
    BusConfig wrong = config(kController, BusRole::kController, "node-w");
    wrong.password = "not-the-password";
    Node node(wrong);
    ASSERT_TRUE(
        runUntil({&node}, [&] { return node.bus->counters().at("bus.failed_attempts") >= 1; }));
    runUntil(
        {&node}, [] { return false; }, std::chrono::milliseconds(500));
    EXPECT_FALSE(node.bus->connected());
    ASSERT_EQ(node.lines.size(), 1u) << ::testing::PrintToString(node.lines);
    EXPECT_EQ(node.lines[0],
              "bus: the broker at mqtt://127.0.0.1:" + std::to_string(broker_->port()) +
                  " refused the connection as \"vpe-controller\": Not authorized "
                  "(reason 135; check [bus] username and password, and the "
                  "broker's password file); playing on alone, asking again every "
                  "5 s");
}

TEST_F(LightBusTest, AnAbsentBrokerIsOneLineAndTheBusConnectsWhenItComes) {
    Node node(config(kPlayer, BusRole::kPlayer, "node-b"));
    runUntil(
        {&node}, [] { return false; }, std::chrono::milliseconds(1200));
    EXPECT_GE(node.bus->counters().at("bus.failed_attempts"), 3u);  // it kept trying
    ASSERT_EQ(node.lines.size(), 1u) << ::testing::PrintToString(node.lines);
    EXPECT_EQ(node.lines[0], "bus: cannot reach the broker at mqtt://127.0.0.1:" +
                                 std::to_string(broker_->port()) +
                                 " (Connection refused); playing on with this node's own light, "
                                 "trying again every 0.25 s");
    broker_->start();
    const auto started = std::chrono::steady_clock::now();
    ASSERT_TRUE(runUntil({&node}, [&] { return node.bus->connected(); }));
    EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::milliseconds(700));

    // The broker goes away and comes back: lost once, connected again on its own.
    broker_->stop(SIGKILL);
    ASSERT_TRUE(runUntil({&node}, [&] { return !node.bus->connected(); }));
    EXPECT_EQ(node.linesWith("bus: lost the broker at"), 1u);
    broker_->start();
    ASSERT_TRUE(runUntil({&node}, [&] { return node.bus->connected(); }));
    EXPECT_EQ(node.linesWith("bus: connected to"), 2u);
}

TEST_F(LightBusTest, RefusesAndCountsMalformedAndOutOfRangeMessages) {
    broker_->start();
    Node node(config(kPlayer, BusRole::kPlayer, "node-b"));
    // A raw client with a controller's credentials, publishing whatever it likes.
    MqttSettings raw;
    raw.port = broker_->port();
    raw.clientId = "raw";
    raw.username = kController.name;
    raw.password = kController.password;
    MqttConnection sender(raw, {});
    ASSERT_TRUE(runUntil({&node}, [&] {
        sender.service(monotonicNowNs());
        return sender.connected() && node.bus->connected();
    }));
    const std::int64_t nowUs = realtimeNowNs() / 1000;
    const auto state = [&](const std::string& azimuth, std::int64_t timeUs,
                           const std::string& preset) {
        return "{\"format\":1,\"node\":\"raw\",\"seq\":1,\"time_us\":" + std::to_string(timeUs) +
               ",\"azimuth\":" + azimuth +
               ",\"elevation\":30,\"distance\":0.6,\"from\":{\"time_us\":" +
               std::to_string(timeUs) +
               ",\"azimuth\":0,\"elevation\":30,\"distance\":0.6},\"drift_us\":null,\"preset\":\"" +
               preset + "\"}";
    };
    const std::vector<std::string> payloads{
        "not json at all",
        "{\"format\":1}",
        state("500", nowUs, ""),               // outside the board's azimuth
        state("10", nowUs + 60'000'000, ""),   // a minute ahead of this clock
        state("12", nowUs, "gold"),            // followed, its preset refused
        state("13", nowUs + 1000, "stripes"),  // good
    };
    for (const std::string& payload : payloads) {
        ASSERT_TRUE(sender.publish("vpe/test/light", payload, 1, false).has_value());
    }
    ASSERT_TRUE(runUntil({&node}, [&] {
        sender.service(monotonicNowNs());
        return node.bus->counters().at("bus.received") == payloads.size();
    })) << ::testing::PrintToString(node.lines);
    const auto refused = node.bus->refusals();
    EXPECT_EQ(refused.at("bus.malformed"), 2u);
    EXPECT_EQ(refused.at("bus.out_of_range"), 1u);
    EXPECT_EQ(refused.at("bus.clock_ahead"), 1u);
    EXPECT_EQ(refused.at("bus.unknown_preset"), 1u);
    // Only the two that may move the light did.
    ASSERT_EQ(node.events.size(), 2u);
    EXPECT_EQ(std::get<FollowLight>(node.events[0].action).state.target.azimuthDeg, 12);
    EXPECT_EQ(std::get<FollowLight>(node.events[0].action).state.preset, -1);
    EXPECT_EQ(std::get<FollowLight>(node.events[1].action).state.preset, 0);
    EXPECT_EQ(node.linesWith("bus: vpe/test/light: not JSON (malformed)"), 1u);
    EXPECT_EQ(node.linesWith("bus: vpe/test/light: azimuth 500 is outside [-100, 100] "
                             "(out_of_range)"),
              1u);
    EXPECT_EQ(node.linesWith("s ahead of this node's clock; synchronise the clocks"), 1u);
    // Five refusals logged at once, then the rate limit: a flood cannot fill the journal.
    for (int i = 0; i < 50; ++i) {
        sender.publish("vpe/test/light", "garbage", 0, false);
    }
    runUntil({&node}, [&] {
        sender.service(monotonicNowNs());
        return node.bus->refusals().at("bus.malformed") == 52u;
    });
    EXPECT_EQ(node.bus->refusals().at("bus.malformed"), 52u);
    EXPECT_LE(node.lines.size(), 7u) << ::testing::PrintToString(node.lines);
}

// The optional TLS listener (docs/multi-node.md, "TLS"): a CA of the show's own, the broker's
// certificate naming its address. The handshake runs in the player's loop like the rest;
// a node that does not trust the broker's certificate plays on alone, one line.
// The control page's side: every node's status goes out retained on vpe/<show>/status/<id>
// (a viewer may read it), the show's blackout switch reaches the node, a bad switch message is
// refused and counted, and a viewer may not switch it.
TEST_F(LightBusTest, PublishesItsStatusAndFollowsTheBlackoutSwitch) {
    broker_ = std::make_unique<MosquittoBroker>(folder_, std::vector{kController, kPlayer, kViewer},
                                                showAcl());
    broker_->start();
    Node node(config(kPlayer, BusRole::kPlayer, "node-b"));
    std::vector<bool> switched;
    node.bus->onBlackout([&](bool on) { switched.push_back(on); });
    std::vector<std::pair<std::string, std::string>> seen;
    const auto client = [&](const BrokerUser& user, const std::string& id) {
        MqttSettings settings;
        settings.port = broker_->port();
        settings.clientId = id;
        settings.username = user.name;
        settings.password = user.password;
        settings.subscriptions = {"vpe/test/status/+"};
        return settings;
    };
    MqttConnection::Handlers watching;
    watching.message = [&](std::string_view topic, std::string_view payload, bool) {
        seen.emplace_back(topic, payload);
    };
    MqttConnection viewer(client(kViewer, "page-viewer"), watching);
    std::vector<int> acknowledgements;
    MqttConnection::Handlers steering;
    steering.acknowledged = [&](int, int reason) { acknowledgements.push_back(reason); };
    MqttConnection page(client(kController, "page"), steering);
    MqttConnection viewerSwitch(client(kViewer, "page-viewer-2"), steering);
    const auto serve = [&] {
        viewer.service(monotonicNowNs());
        page.service(monotonicNowNs());
        viewerSwitch.service(monotonicNowNs());
    };
    ASSERT_TRUE(runUntil({&node}, [&] {
        serve();
        return viewer.connected() && page.connected() && viewerSwitch.connected() &&
               node.bus->connected();
    })) << broker_->log();

    NodeStatus status;
    status.timeUs = realtimeNowNs() / 1000;
    status.fps = 60;
    status.presets = {"stripes", "radial"};
    node.bus->publishStatus(status);
    ASSERT_TRUE(runUntil({&node}, [&] {
        serve();
        return !seen.empty();
    }));
    EXPECT_EQ(seen.at(0).first, "vpe/test/status/node-b");
    const auto json = nlohmann::json::parse(seen.at(0).second);
    EXPECT_EQ(json["node"], "node-b");
    EXPECT_EQ(json["role"], "player");
    EXPECT_EQ(json["blackout"], false);
    EXPECT_EQ(node.bus->counters().at("bus.status_published"), 1u);

    const std::int64_t nowUs = realtimeNowNs() / 1000;
    const auto blackout = [&](bool on, std::int64_t timeUs) {
        return encodeBlackoutMessage({"page", timeUs, on});
    };
    // A viewer's switch is refused by the broker and never arrives.
    ASSERT_TRUE(viewerSwitch.publish("vpe/test/blackout", blackout(true, nowUs), 1, true));
    ASSERT_TRUE(runUntil({&node}, [&] {
        serve();
        return !acknowledgements.empty();
    }));
    EXPECT_GE(acknowledgements.at(0), 0x80);
    ASSERT_TRUE(page.publish("vpe/test/blackout", "{\"format\":1,\"on\":\"yes\"}", 1, false));
    ASSERT_TRUE(page.publish("vpe/test/blackout", blackout(true, nowUs + 1), 1, true));
    ASSERT_TRUE(page.publish("vpe/test/blackout", blackout(false, nowUs), 1, false));  // older
    ASSERT_TRUE(runUntil({&node}, [&] {
        serve();
        return node.bus->counters().at("bus.received") == 3;
    })) << ::testing::PrintToString(node.lines);
    EXPECT_EQ(switched, std::vector<bool>{true});
    EXPECT_TRUE(node.bus->blackout());
    EXPECT_EQ(node.bus->refusals().at("bus.malformed"), 1u);
    EXPECT_EQ(node.linesWith("bus: vpe/test/blackout: \"node\": expected a name of 1-64 bytes "
                             "(malformed)"),
              1u)
        << ::testing::PrintToString(node.lines);
    EXPECT_EQ(node.linesWith("bus: blackout on (from \"page\")"), 1u);
    EXPECT_NE(node.bus->lastError().find("malformed"), std::string::npos);
    node.bus->publishStatus(status);
    ASSERT_TRUE(runUntil({&node}, [&] {
        serve();
        return seen.size() == 2;
    }));
    EXPECT_EQ(nlohmann::json::parse(seen.at(1).second)["blackout"], true);
}

TEST_F(LightBusTest, ConnectsOverTlsAndRefusesABrokerItCannotTrust) {
    if (::access("/usr/bin/openssl", X_OK) != 0) {
        GTEST_SKIP() << "/usr/bin/openssl is absent (Debian's openssl)";
    }
    const fs::path certs = folder_ / "certs";
    fs::create_directories(certs);
    std::ofstream(certs / "san.cnf") << "subjectAltName=IP:127.0.0.1\n";
    const std::string key = "-newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes ";
    const std::string in = "cd '" + certs.string() + "' && ";
    for (const std::string& command :
         {in + "openssl req -x509 " + key + "-days 1 -subj /CN=show-ca -keyout ca.key -out ca.crt",
          in + "openssl req -x509 " + key +
              "-days 1 -subj /CN=other-ca -keyout other.key -out other.crt",
          in + "openssl req " + key + "-subj /CN=broker -keyout broker.key -out broker.csr",
          in + "openssl x509 -req -in broker.csr -CA ca.crt -CAkey ca.key -CAcreateserial -days 1 "
               "-extfile san.cnf -out broker.crt"}) {
        ASSERT_EQ(std::system((command + " >/dev/null 2>&1").c_str()), 0) << command;
    }
    broker_.reset();
    broker_ = std::make_unique<MosquittoBroker>(
        folder_ / "tls", std::vector{kController, kPlayer}, showAcl(), 0,
        "cafile " + (certs / "ca.crt").string() + "\ncertfile " + (certs / "broker.crt").string() +
            "\nkeyfile " + (certs / "broker.key").string() + "\n");
    broker_->start();

    BusConfig trusting = config(kController, BusRole::kController, "node-a");
    trusting.cafile = certs / "ca.crt";
    Node controller(trusting);
    BusConfig follower = config(kPlayer, BusRole::kPlayer, "node-b");
    follower.cafile = certs / "ca.crt";
    Node player(follower);
    ASSERT_TRUE(runUntil({&controller, &player},
                         [&] { return controller.bus->connected() && player.bus->connected(); }))
        << ::testing::PrintToString(controller.lines) << broker_->log();
    EXPECT_EQ(controller.bus->description().substr(0, 15), "bus (mqtts://12");
    controller.bus->offer(someState(), monotonicNowNs());
    ASSERT_TRUE(runUntil({&controller, &player}, [&] { return !player.events.empty(); }));
    EXPECT_EQ(std::get<FollowLight>(player.events[0].action).state.target.azimuthDeg, -42.5);

    BusConfig doubting = config(kPlayer, BusRole::kPlayer, "node-c");
    doubting.cafile = certs / "other.crt";
    Node stranger(doubting);
    runUntil(
        {&stranger}, [] { return false; }, std::chrono::milliseconds(800));
    EXPECT_FALSE(stranger.bus->connected());
    EXPECT_GE(stranger.bus->counters().at("bus.failed_attempts"), 2u);
    ASSERT_EQ(stranger.lines.size(), 1u) << ::testing::PrintToString(stranger.lines);
    EXPECT_NE(stranger.lines[0].find("bus: cannot reach the broker at mqtts://127.0.0.1:"),
              std::string::npos)
        << stranger.lines[0];
}

}  // namespace
}  // namespace vpe::firmware::bus
