// SPDX-License-Identifier: MIT
// Three vpe-player nodes, headless at 60 Hz on the GLES tests' vase (160 × 90), sharing one light
// through a broker of the test's own: one steered by replayed knob turns, two following. Their
// --light-log files are compared at equal presentation times (light_log_agreement.h): every
// node agrees with the steered one within one 60 Hz frame at p99, the idle drift included.
// Then the faults: a node started before the broker, the broker killed and restarted, a node
// killed and restarted, a node with the wrong password: nothing crashes, no node stops
// drawing, and the light converges again within a second. SKIPs without mosquitto or EGL.
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <nlohmann/json.hpp>
#include <sys/socket.h>
#include <unistd.h>

#include "vpe/firmware/loop/show_clock.h"

#include "child_process.h"
#include "light_log_agreement.h"
#include "mosquitto_broker.h"
#include "replay_script.h"
#include "test_paths.h"

namespace vpe::firmware::bus {
namespace {

namespace fs = std::filesystem;
using namespace testing;
using namespace std::chrono_literals;

constexpr double kFrameMs = 1000.0 / 60.0;

std::string readAll(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::size_t count(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t at = text.find(needle); at != std::string::npos;
         at = text.find(needle, at + 1)) {
        ++n;
    }
    return n;
}

bool waitFor(const std::function<bool()>& condition, std::chrono::milliseconds limit = 5000ms) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
        if (condition()) {
            return true;
        }
        std::this_thread::sleep_for(10ms);
    }
    return condition();
}

std::int64_t nowUs() {
    return realtimeNowNs() / 1000;
}

// A UDP port on 127.0.0.1 nothing listens on now.
int freeUdpPort() {
    const int probe = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    ::bind(probe, reinterpret_cast<const sockaddr*>(&address), length);
    ::getsockname(probe, reinterpret_cast<sockaddr*>(&address), &length);
    ::close(probe);
    return ntohs(address.sin_port);
}

// One OSC message with one float, as TouchDesigner's OSC Out sends it (proto/OSC.md).
void sendOsc(int port, const std::string& path, float value) {
    std::string datagram = path;
    datagram.append(4 - path.size() % 4, '\0');
    datagram += std::string(",f\0\0", 4);
    std::uint32_t bits = 0;
    std::memcpy(&bits, &value, 4);
    bits = htonl(bits);
    datagram.append(reinterpret_cast<const char*>(&bits), 4);
    const int sender = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in target{};
    target.sin_family = AF_INET;
    target.sin_port = htons(static_cast<std::uint16_t>(port));
    target.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::sendto(sender, datagram.data(), datagram.size(), 0,
             reinterpret_cast<const sockaddr*>(&target), sizeof target);
    ::close(sender);
}

// One vpe-player node: its board, its process, its files.
struct PlayerNode {
    std::string name;
    fs::path folder;
    ChildProcess process;
    int runs = 0;

    fs::path log() const { return folder / (name + "-" + std::to_string(runs) + ".jsonl"); }
    fs::path err() const { return folder / (name + "-" + std::to_string(runs) + ".err"); }
    fs::path out() const { return folder / (name + "-" + std::to_string(runs) + ".out"); }
    std::string stderrText() const { return readAll(err()); }
    nlohmann::json report() const {
        const std::string text = readAll(out());
        const std::size_t open = text.rfind("\n{");
        return open == std::string::npos
                   ? nlohmann::json()
                   : nlohmann::json::parse(text.substr(open + 1), nullptr, false);
    }
    void start(const fs::path& bundle, std::vector<std::string> extra) {
        ++runs;
        std::vector<std::string> arguments{test_paths::playerPath(),
                                           "--board",
                                           (folder / (name + ".toml")).string(),
                                           "--bundle",
                                           bundle.string(),
                                           "--light-log",
                                           log().string(),
                                           "--json"};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        process = ChildProcess(arguments, out(), err());
    }
    bool connected() const { return stderrText().find("bus: connected to") != std::string::npos; }
};

class MultiNodeTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (const auto why = MosquittoBroker::unavailable()) {
            GTEST_SKIP() << *why;
        }
        folder_ = fs::temp_directory_path() /
                  ("vpe-multi-node-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(folder_);
        bundle_ = folder_ / "scene.vpeb";
        const std::string command = std::string(test_paths::writeTestBundlePath()) + " --out '" +
                                    bundle_.string() + "' --size 160x90 >/dev/null";
        ASSERT_EQ(std::system(command.c_str()), 0);
        // The player itself says whether this machine draws headless: one frame, no bus.
        std::ofstream(folder_ / "alone.toml") << "[display]\nbackend = \"headless\"\n";
        const std::string alone = std::string(test_paths::playerPath()) + " --board '" +
                                  (folder_ / "alone.toml").string() + "' --bundle '" +
                                  bundle_.string() + "' --frames 1 >/dev/null 2>'" +
                                  (folder_ / "alone.err").string() + "'";
        if (std::system(alone.c_str()) != 0) {
            const std::string why = readAll(folder_ / "alone.err");
            fs::remove_all(folder_);
            GTEST_SKIP() << "no headless OpenGL ES here: " << why;
        }
        broker_ = std::make_unique<MosquittoBroker>(folder_ / "broker",
                                                    std::vector{kController, kPlayer}, showAcl());
    }
    void TearDown() override {
        nodes_.clear();
        broker_.reset();
        if (!HasFailure()) {
            fs::remove_all(folder_);
        } else {
            std::cerr << "the nodes' files are kept in " << folder_ << "\n";
        }
    }

    // A headless node at 60 Hz with the replay's knobs (switched off: a replay decodes with
    // them), no OSC, and the bus.
    PlayerNode& node(const std::string& name, const BrokerUser& user, const std::string& role,
                     const std::string& password = "",
                     const std::string& osc = "[osc]\nenabled = false\n") {
        std::ofstream(folder_ / (name + ".toml"))
            << "[display]\nbackend = \"headless\"\n[render]\nrate = 60\n"
            << "[light]\nazimuth = [-90, 90]\nelevation = [0, 80]\ndistance = [0.05, 5]\n"
            << "initial_distance = 0.6\nsmoothing_s = 0.12\n"
            << "[idle]\nenabled = true\nquiet_s = 1.5\nperiod_s = 6\nhandover_s = 0.5\n"
            << osc << "[bus]\nhost = \"127.0.0.1\"\nport = " << broker_->port() << "\nusername = \""
            << user.name << "\"\npassword = \"" << (password.empty() ? user.password : password)
            << "\"\nshow = \"test\"\nrole = \"" << role << "\"\nclient_id = \"" << name << "\"\n"
            << vpe::testing::replayBoardInputs(false);
        nodes_.push_back(std::make_unique<PlayerNode>(PlayerNode{name, folder_, {}, 0}));
        return *nodes_.back();
    }

    fs::path folder_, bundle_;
    std::unique_ptr<MosquittoBroker> broker_;
    std::vector<std::unique_ptr<PlayerNode>> nodes_;
};

TEST_F(MultiNodeTest, ThreeNodesAgreeWithinAFrame) {
    broker_->start();
    PlayerNode& b = node("node-b", kPlayer, "player");
    PlayerNode& c = node("node-c", kPlayer, "player");
    PlayerNode& a = node("node-a", kController, "controller");
    b.start(bundle_, {});
    c.start(bundle_, {});
    ASSERT_TRUE(waitFor([&] { return b.connected() && c.connected(); }))
        << b.stderrText() << c.stderrText();

    // Turns of both knobs, fast and slow, then single detents; then quiet: the drift.
    vpe::testing::ReplayScript script;
    double t = script.knobTurn(17, 18, 0.5, 10, 0.05);
    t = script.knobTurn(22, 23, t + 0.3, 8, 0.04);
    t = script.knobTurn(17, 18, t + 0.3, -15, 0.03);
    for (int k = 0; k < 4; ++k) {
        t = script.knobTurn(17, 18, t + 0.5, k % 2 == 0 ? 1 : -1, 0.05);
    }
    const fs::path replay = folder_ / "knobs.jsonl";
    script.write(replay);
    // The replay ends near 4.5 s; 1.5 s quiet, the drift for the rest of the 9 s.
    a.start(bundle_, {"--replay", replay.string(), "--frames", "540"});
    const auto status = a.process.wait(30000ms);
    ASSERT_TRUE(status.has_value());
    EXPECT_EQ(*status, 0) << a.stderrText();
    EXPECT_EQ(b.process.stop(), 0) << b.stderrText();
    EXPECT_EQ(c.process.stop(), 0) << c.stderrText();

    const LightTrack reference = readLightLog(a.log());
    ASSERT_GT(reference.size(), 400u);
    const std::int64_t from = reference.front().tUs + 200'000, to = reference.back().tUs - 200'000;
    for (PlayerNode* follower : {&b, &c}) {
        const Agreement agreement =
            compareTracks(reference, readLightLog(follower->log()), from, to);
        ASSERT_GT(agreement.lagsMs.size(), 400u) << follower->name;
        std::cout << follower->name << " against node-a: " << agreement.lagsMs.size()
                  << " frames, lag p50 " << agreement.percentile(0.5) << " ms, p99 "
                  << agreement.percentile(0.99) << " ms, max " << agreement.percentile(1.0)
                  << " ms, apart " << agreement.apart << "\n";
        EXPECT_LE(agreement.percentile(0.99), kFrameMs)
            << follower->name << ": p50 " << agreement.percentile(0.5) << " ms, apart "
            << agreement.apart;
        EXPECT_LE(agreement.apart, agreement.lagsMs.size() / 100) << follower->name;
        EXPECT_LT(largestGapMs(readLightLog(follower->log()), from, to), 100.0) << follower->name;
    }
    // Every state went out and came in; the drift was drawn alike without a message.
    const nlohmann::json aReport = a.report(), bReport = b.report();
    EXPECT_EQ(aReport["events"]["knobs"], 37) << aReport.dump();
    EXPECT_GE(aReport["counters"]["bus.published"].get<int>(), 10) << aReport.dump();
    EXPECT_EQ(aReport["counters"]["bus.publish_refused"], 0);
    EXPECT_GE(bReport["counters"]["bus.received"].get<int>(), 10) << bReport.dump();
    EXPECT_EQ(bReport["events_refused"], 0);
    EXPECT_EQ(aReport["light"]["active"], "idle");
    EXPECT_EQ(reference.back().active, "idle");
    const std::size_t drifting = static_cast<std::size_t>(
        std::count_if(reference.begin(), reference.end(),
                      [](const LightSample& s) { return s.active == "idle"; }));
    EXPECT_GT(drifting, 60u);  // over a second of the drift compared
}

TEST_F(MultiNodeTest, RidesOutBrokerAndNodeFailures) {
    PlayerNode& b = node("node-b", kPlayer, "player");
    PlayerNode& c = node("node-c", kPlayer, "player");
    PlayerNode& a = node("node-a", kController, "controller");
    PlayerNode& d = node("node-d", kPlayer, "player", "wrong-password");
    // Broker absent at start: one line, and the node plays on.
    b.start(bundle_, {});
    ASSERT_TRUE(waitFor(
        [&] { return b.stderrText().find("cannot reach the broker") != std::string::npos; }));
    broker_->start();
    ASSERT_TRUE(waitFor([&] { return b.connected(); })) << b.stderrText();
    c.start(bundle_, {});
    d.start(bundle_, {});
    // The controller turns a knob every 0.2 s, over and over.
    vpe::testing::ReplayScript script;
    double t = 0.1;
    for (int k = 0; k < 12; ++k) {
        t = script.knobTurn(17, 18, t + 0.15, k % 4 < 2 ? 2 : -2, 0.03);
    }
    const fs::path replay = folder_ / "loop.jsonl";
    script.write(replay);
    a.start(bundle_, {"--replay", replay.string(), "--replay-loop"});
    ASSERT_TRUE(waitFor([&] { return a.connected() && c.connected(); }))
        << a.stderrText() << c.stderrText();
    std::this_thread::sleep_for(1500ms);

    // The broker dies; the controller steers on; the broker comes back.
    const std::int64_t brokerDied = nowUs();
    broker_->stop(SIGKILL);
    std::this_thread::sleep_for(1500ms);
    broker_->start();
    const std::int64_t brokerBack = nowUs();
    std::this_thread::sleep_for(2500ms);

    // A node dies and comes back: it takes the retained state.
    const fs::path cFirstLog = c.log();
    c.process.signal(SIGKILL);
    c.process.wait(2000ms);
    std::this_thread::sleep_for(500ms);
    c.start(bundle_, {});
    ASSERT_TRUE(waitFor([&] { return fs::exists(c.log()) && fs::file_size(c.log()) > 0; }));
    // Its frames are judged until 0.2 s before its last: on a loaded machine (the whole suite on
    // two cores) its connection could come later than the 2.5 s this used to give it in all.
    ASSERT_TRUE(waitFor([&] { return c.connected(); })) << c.stderrText();
    std::this_thread::sleep_for(2500ms);

    for (PlayerNode* n : {&a, &b, &c, &d}) {
        EXPECT_EQ(n->process.stop(), 0) << n->name << ": " << n->stderrText();
    }
    const LightTrack reference = readLightLog(a.log());
    const LightTrack bTrack = readLightLog(b.log());
    // The outage was felt (the controller moved, the others could not hear of it) ...
    const Agreement outage = compareTracks(reference, bTrack, brokerDied + 300'000, brokerBack);
    EXPECT_GT(outage.percentile(1.0), kFrameMs) << "the broker's absence changed nothing?";
    // ... and healed within a second of the broker's return, for good.
    for (const fs::path& log : {b.log(), cFirstLog}) {
        const auto settled =
            settledFrom(reference, readLightLog(log), brokerBack, brokerBack + 2'000'000, kFrameMs);
        ASSERT_TRUE(settled.has_value()) << log;
        EXPECT_LE(*settled - brokerBack, 1'000'000) << log;
    }
    // The restarted node agrees within a second of its first frame.
    const LightTrack restarted = readLightLog(c.log());
    ASSERT_FALSE(restarted.empty());
    const std::int64_t firstFrame = restarted.front().tUs;
    const auto settled =
        settledFrom(reference, restarted, firstFrame, restarted.back().tUs - 200'000, kFrameMs);
    ASSERT_TRUE(settled.has_value());
    EXPECT_LE(*settled - firstFrame, 1'000'000);
    // No node stopped drawing, the outage included.
    for (const fs::path& log : {a.log(), b.log(), d.log()}) {
        const LightTrack track = readLightLog(log);
        EXPECT_LT(largestGapMs(track, track.front().tUs, track.back().tUs), 100.0) << log;
    }
    // One line each: the broker absent at start, lost, and back.
    const std::string bErr = b.stderrText();
    EXPECT_EQ(count(bErr, "cannot reach the broker"), 1u) << bErr;
    EXPECT_EQ(count(bErr, "lost the broker"), 1u) << bErr;
    EXPECT_EQ(count(bErr, "bus: connected to"), 2u) << bErr;
    // The wrong password: one line over every retry, drawing all along, never connected.
    const std::string dErr = d.stderrText();
    EXPECT_EQ(count(dErr, "refused the connection as \"vpe-player\""), 1u) << dErr;
    EXPECT_EQ(count(dErr, "vpe-player: "), 2u) << dErr;  // its description, and that line
    EXPECT_EQ(d.report()["counters"]["bus.connections"], 0) << d.report().dump();
    EXPECT_GT(d.report()["frames"].get<int>() + d.report()["skipped"].get<int>(), 400);
}

// TouchDesigner or QLab steer every node at once through a controller's OSC: the controller
// republishes what OSC did; a node whose [osc] allow list leaves the sender out refuses it and
// counts it in its report.
TEST_F(MultiNodeTest, OscOnAControllerSteersEveryNode) {
    broker_->start();
    const int controllerPort = freeUdpPort(), playerPort = freeUdpPort();
    PlayerNode& a =
        node("node-a", kController, "controller", "",
             "[osc]\naddress = \"127.0.0.1\"\nport = " + std::to_string(controllerPort) +
                 "\nallow = [\"127.0.0.1\"]\n");
    PlayerNode& b = node("node-b", kPlayer, "player", "",
                         "[osc]\naddress = \"127.0.0.1\"\nport = " + std::to_string(playerPort) +
                             "\nallow = [\"192.0.2.0/24\"]\n");
    a.start(bundle_, {});
    b.start(bundle_, {});
    ASSERT_TRUE(waitFor([&] { return a.connected() && b.connected(); }))
        << a.stderrText() << b.stderrText();
    EXPECT_NE(b.stderrText().find("osc (127.0.0.1:" + std::to_string(playerPort) +
                                  ", from 192.0.2.0/24)"),
              std::string::npos)
        << b.stderrText();
    sendOsc(controllerPort, "/vpe/light/azimuth", 30.0f);
    sendOsc(controllerPort, "/vpe/light/elevation", 20.0f);
    sendOsc(playerPort, "/vpe/light/azimuth", -50.0f);  // not from the gallery's network
    std::this_thread::sleep_for(900ms);  // the move all but settles (τ 0.12 s: within 0.1°)
    EXPECT_EQ(a.process.stop(), 0) << a.stderrText();
    EXPECT_EQ(b.process.stop(), 0) << b.stderrText();

    const nlohmann::json aReport = a.report(), bReport = b.report();
    EXPECT_EQ(aReport["events"]["osc"], 2) << aReport.dump();
    EXPECT_EQ(aReport["light"]["active"], "osc");
    EXPECT_GE(aReport["counters"]["bus.published"].get<int>(), 1);
    EXPECT_NEAR(bReport["light"]["azimuth"].get<double>(), 30.0, 0.1) << bReport.dump();
    EXPECT_NEAR(bReport["light"]["elevation"].get<double>(), 20.0, 0.1) << bReport.dump();
    EXPECT_EQ(bReport["light"]["active"], "bus");
    EXPECT_EQ(bReport["refused"]["osc.source_not_allowed"], 1) << bReport.dump();
    EXPECT_EQ(bReport["events"].value("osc", 0), 0);
    EXPECT_NE(b.stderrText().find("osc: datagram of 28 bytes from 127.0.0.1:"), std::string::npos)
        << b.stderrText();
}

}  // namespace
}  // namespace vpe::firmware::bus
