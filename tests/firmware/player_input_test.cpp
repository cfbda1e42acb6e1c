// SPDX-License-Identifier: MIT
// vpe-player with inputs, end to end on the real binary: --check, replayed knob edges (with
// bounce), OSC messages and camera frames through the real decoders, absent hardware logged
// once, and a bundle reloaded on SIGHUP or when its file is replaced (a bad one refused while
// the old keeps playing). Runs that render SKIP without EGL.
#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include "player_fixture.h"
#include "replay_script.h"

namespace vpe::firmware {
namespace {

using namespace vpe::firmware::testing;
using vpe::testing::ReplayScript;

// replayBoardInputs' knobs and camera (switched on: absent here); no smoothing and no drift,
// so the final light is exact.
const std::string kInputs = vpe::testing::replayBoardInputs(true) + R"(
[light]
azimuth = [-90, 90]
elevation = [0, 80]
initial_azimuth = 0
initial_elevation = 30
smoothing_s = 0
[idle]
enabled = false
[render]
rate = 0
)";

std::string jsonOf(const PlayerRun& run) {
    const std::size_t open = run.out.rfind("\n{");
    return open == std::string::npos ? "" : run.out.substr(open + 1);
}

double number(const std::string& json, const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? -1e9 : std::stod(json.substr(at + key.size() + 4));
}

class PlayerInputTest : public PlayerTest {
protected:
    void SetUp() override {
        PlayerTest::SetUp();
        board_ =
            writeFile("inputs.toml", std::string("[display]\nbackend = \"headless\"\n") + kInputs);
    }
    fs::path board_;
};

TEST_F(PlayerInputTest, ChecksABoardFile) {
    const PlayerRun ok = play({"--board", board_.string(), "--check"});
    EXPECT_EQ(ok.status, 0) << ok.err;
    EXPECT_NE(ok.out.find("inputs.toml: valid board file"), std::string::npos) << ok.out;
    EXPECT_NE(ok.out.find("knobs: 2 encoders, 1 buttons on gpiochip9 (absent on this machine)"),
              std::string::npos)
        << ok.out;
    EXPECT_NE(ok.out.find("camera: auto, 320x240, 4 calibration points"), std::string::npos)
        << ok.out;
    const PlayerRun withBundle =
        play({"--board", board_.string(), "--bundle", bundle_.string(), "--check"});
    EXPECT_EQ(withBundle.status, 0) << withBundle.err;
    EXPECT_NE(withBundle.out.find("ok (checksum verified), projector 160x120, 2 presets"),
              std::string::npos)
        << withBundle.out;
    for (const auto& [name, text, needle] : std::vector<std::array<std::string, 3>>{
             {"collinear.toml",
              "[display]\nbackend = \"headless\"\n[camera]\ncalibration = [[0, 0, 0, 0], [1, 1, "
              "1, 1], [2, 2, 2, 2]]\n",
              "collinear.toml:camera.calibration"},
             {"axis.toml",
              "[display]\nbackend = \"headless\"\n[gpio]\n[[gpio.encoder]]\na = 1\nb = 2\naxis = "
              "\"roll\"\n",
              "axis.toml:gpio.encoder[0].axis"},
             {"port.toml", "[display]\nbackend = \"headless\"\n[osc]\nport = 70000\n",
              "port.toml:osc.port"},
             {"size.toml", "[display]\nbackend = \"headless\"\n[render]\nsize = \"320x240\"\n",
              "size.toml:render.size: 320x240 differs from the bundle's projector 160x120"}}) {
        const fs::path bad = writeFile(name, text);
        expectOneLineError(play({"--board", bad.string(), "--bundle", bundle_.string(), "--check"}),
                           needle);
    }
}

TEST_F(PlayerInputTest, ReplaysKnobsOscAndCameraThroughTheDecoders) {
    std::string why;
    if (!headlessAvailable(why)) {
        GTEST_SKIP() << "no headless OpenGL ES 3.1: " << why;
    }
    ReplayScript script;
    // 10 clicks clockwise and 3 back, bouncing: +14°; then 5 clicks up: +5°.
    double t = script.knobTurn(17, 18, 0.05, 10, 0.02, 0.002, 2);
    t = script.knobTurn(17, 18, t, -3, 0.02, 0.002, 3);
    t = script.knobTurn(22, 23, t, 5, 0.02);
    script.buttonPress(27, t, 0.05);
    const fs::path knobs = folder_ / "knobs.jsonl";
    script.write(knobs);
    PlayerRun run = play({"--board", board_.string(), "--bundle", bundle_.string(), "--replay",
                          knobs.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    std::string json = jsonOf(run);
    EXPECT_EQ(number(json, "azimuth"), 14.0) << json;
    EXPECT_EQ(number(json, "elevation"), 35.0) << json;
    EXPECT_EQ(number(json, "knobs"), 19.0) << json;  // 18 detents and a press
    EXPECT_NE(json.find("\"preset\": \"radial\""), std::string::npos) << json;
    EXPECT_NE(json.find("\"stopped_by\": \"replay\""), std::string::npos) << json;
    EXPECT_EQ(number(json, "events"), 19.0) << json;  // latency samples, one per event
    // Absent hardware is not opened during a replay: the only log line names the replay.
    EXPECT_EQ(run.err.find("gpiochip9"), std::string::npos) << run.err;

    ReplayScript mixed;
    mixed.osc(0.05, "/vpe/light/azimuth", "30");
    mixed.osc(0.06, "/vpe/light/azimuth", "300");  // beyond ±180: refused by the dispatcher
    mixed.osc(0.07, "/vpe/light/elevation", "20.5");
    mixed.osc(0.08, "/vpe/light/elevation", "-95");  // below -90: refused
    mixed.osc(0.09, "/vpe/light/colour", "1");       // not an address of proto/OSC.md
    const fs::path oscOnly = folder_ / "osc.jsonl";
    mixed.write(oscOnly);
    run = play({"--board", board_.string(), "--bundle", bundle_.string(), "--replay",
                oscOnly.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    json = jsonOf(run);
    EXPECT_EQ(number(json, "azimuth"), 30.0) << json;
    EXPECT_EQ(number(json, "elevation"), 20.5) << json;
    EXPECT_EQ(number(json, "osc"), 2.0) << json;
    // Every refusal reaches the report, per reason.
    EXPECT_EQ(number(json, "events_refused"), 3.0) << json;
    EXPECT_EQ(number(json, "osc.out_of_range"), 2.0) << json;
    EXPECT_EQ(number(json, "osc.unknown_address"), 1.0) << json;
    EXPECT_NE(
        run.err.find("vpe-player: osc: /vpe/light/azimuth i: azimuth 300 is outside [-90, 90]"),
        std::string::npos)
        << run.err;

    // The lamp at the image centre: azimuth 0, elevation 30 by the calibration; then lost.
    ReplayScript camera;
    for (int frame = 0; frame < 20; ++frame) {
        camera.cameraLamp(0.05 + frame * 0.01, 160, 120 + frame * 0.0);
    }
    camera.osc(0.3, "/vpe/light/azimuth", "-10");
    const fs::path cameraFile = folder_ / "camera.jsonl";
    camera.write(cameraFile);
    run = play({"--board", board_.string(), "--bundle", bundle_.string(), "--replay",
                cameraFile.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    json = jsonOf(run);
    EXPECT_EQ(number(json, "camera"), 20.0) << json;
    EXPECT_NEAR(number(json, "elevation"), 30.0, 0.5) << json;
    EXPECT_EQ(number(json, "azimuth"), -10.0) << json;  // OSC came last: the last active wins
    EXPECT_NE(json.find("\"active\": \"osc\""), std::string::npos) << json;
}

// Paced, a tick whose light and preset equal the frame on show draws nothing: no drift, no
// input, one frame drawn and the rest skipped; a replayed knob turn draws again.
TEST_F(PlayerInputTest, DrawsNothingWhenNothingChanged) {
    std::string why;
    if (!headlessAvailable(why)) {
        GTEST_SKIP() << "no headless OpenGL ES 3.1: " << why;
    }
    std::string paced = kInputs;
    paced.replace(paced.find("rate = 0"), 8, "rate = 200");
    const fs::path board = writeFile("paced.toml", "[display]\nbackend = \"headless\"\n" + paced);
    PlayerRun run =
        play({"--board", board.string(), "--bundle", bundle_.string(), "--frames", "40", "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    std::string json = jsonOf(run);
    EXPECT_EQ(number(json, "frames"), 1.0) << json;
    EXPECT_EQ(number(json, "skipped"), 39.0) << json;

    ReplayScript script;
    script.knobTurn(17, 18, 0.05, 3, 0.02);  // three detents: three new lights
    const fs::path knobs = folder_ / "turn.jsonl";
    script.write(knobs);
    run = play({"--board", board.string(), "--bundle", bundle_.string(), "--replay", knobs.string(),
                "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    json = jsonOf(run);
    EXPECT_GE(number(json, "frames"), 2.0) << json;
    EXPECT_LE(number(json, "frames"), 4.0) << json;
    EXPECT_GT(number(json, "skipped"), 0.0) << json;
    EXPECT_EQ(number(json, "azimuth"), 6.0) << json;  // 2° a detent
}

TEST_F(PlayerInputTest, RefusesBadReplayFiles) {
    const auto refuse = [&](const std::string& text, const std::string& needle) {
        const fs::path file = writeFile("bad.jsonl", text);
        expectOneLineError(play({"--board", board_.string(), "--bundle", bundle_.string(),
                                 "--replay", file.string()}),
                           needle);
    };
    std::string why;
    if (!headlessAvailable(why)) {
        GTEST_SKIP() << "no headless OpenGL ES 3.1: " << why;
    }
    refuse("{\"t\": 0, \"type\": \"gpio\", \"line\": 17, \"edge\": \"up\"}\n",
           "bad.jsonl:1: \"edge\": expected \"rising\" or \"falling\"");
    refuse(
        "{\"t\": 1, \"type\": \"osc\", \"path\": \"/vpe/ping\"}\n{\"t\": 0.5, \"type\": "
        "\"osc\", \"path\": \"/vpe/ping\"}\n",
        "bad.jsonl:2: \"t\" goes back in time");
    refuse("{\"t\": 0, \"type\": \"midi\"}\n", "bad.jsonl:1: \"type\": expected");
    refuse("not json\n", "bad.jsonl:1: not valid JSON");
    refuse("", "bad.jsonl: no events");
    expectOneLineError(play({"--board", board_.string(), "--bundle", bundle_.string(), "--replay",
                             (folder_ / "none.jsonl").string()}),
                       "none.jsonl: cannot read replay file (no such file)");
    const fs::path plain = writeFile("plain.toml", "[display]\nbackend = \"headless\"\n");
    const fs::path gpio = writeFile(
        "gpio.jsonl", "{\"t\": 0, \"type\": \"gpio\", \"line\": 17, \"edge\": \"rising\"}\n");
    expectOneLineError(
        play({"--board", plain.string(), "--bundle", bundle_.string(), "--replay", gpio.string()}),
        "gpio.jsonl:1: a gpio event, but the board's [gpio] has no knobs");
}

TEST_F(PlayerInputTest, LogsAbsentHardwareOnceAndPlays) {
    std::string why;
    if (!headlessAvailable(why)) {
        GTEST_SKIP() << "no headless OpenGL ES 3.1: " << why;
    }
    if (fs::exists("/dev/gpiochip9")) {
        GTEST_SKIP() << "/dev/gpiochip9 exists here";
    }
    const PlayerRun run =
        play({"--board", board_.string(), "--bundle", bundle_.string(), "--frames", "30"});
    ASSERT_EQ(run.status, 0) << run.err;
    const auto count = [&](const std::string& needle) {
        std::size_t n = 0;
        for (std::size_t at = run.err.find(needle); at != std::string::npos;
             at = run.err.find(needle, at + 1)) {
            ++n;
        }
        return n;
    };
    EXPECT_EQ(count("vpe-player: knobs: gpiochip9"), 1u) << run.err;
    EXPECT_EQ(count("playing without them"), 1u) << run.err;
    EXPECT_EQ(count("vpe-player: camera: "), 1u) << run.err;
    EXPECT_NE(run.out.find("30 frames"), std::string::npos) << run.out;
}

TEST_F(PlayerInputTest, ReloadsTheBundleAndRefusesABadOne) {
    std::string why;
    if (!headlessAvailable(why)) {
        GTEST_SKIP() << "no headless OpenGL ES 3.1: " << why;
    }
    const fs::path board =
        writeFile("paced.toml", "[display]\nbackend = \"headless\"\n[render]\nrate = 30\n");
    // The first frame, written out, says the player is drawing: only then may the bundle
    // change (a busy machine once started the player so late that all three reloads came
    // before its first frame, which then drew them as one).
    const fs::path frames = folder_ / "frames";
    const pid_t pid = spawn({"--board", board.string(), "--bundle", bundle_.string(), "--json",
                             "--out", frames.string(), "--every", "1000000"});
    ASSERT_GT(pid, 0);
    const auto waitUntil = [](const auto& condition) {
        for (int i = 0; i < 300; ++i) {
            if (condition()) {
                return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return false;
    };
    const auto waitFor = [&](const std::string& needle) {
        return waitUntil([&] { return spawnedErr().find(needle) != std::string::npos; });
    };
    ASSERT_TRUE(waitUntil([&] { return fs::exists(frames / "frame_00000.ppm"); })) << spawnedErr();
    // Replaced by a corrupt file (written beside it and renamed, as the bake does).
    std::string corrupt = bundleBytes_;
    corrupt[corrupt.size() - 9] = static_cast<char>(corrupt[corrupt.size() - 9] ^ 0x33);
    writeFile("next.tmp", corrupt);
    fs::rename(folder_ / "next.tmp", bundle_);
    EXPECT_TRUE(waitFor("refused, still playing the previous bundle")) << spawnedErr();
    writeFile("next.tmp", bundleBytes_);
    fs::rename(folder_ / "next.tmp", bundle_);
    EXPECT_TRUE(waitFor("reloaded (file replaced)")) << spawnedErr();
    // Two reloads within one tick draw one frame: let the player draw after this one first
    // (six ticks at 30 Hz).
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(waitFor("reloaded (SIGHUP)")) << spawnedErr();
    // Long enough for a dozen ticks at 30 Hz after the reloads, however slow the start was.
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ::kill(pid, SIGTERM);
    const PlayerRun run = finish(pid);
    EXPECT_EQ(run.status, 0) << run.err;
    const std::string json = jsonOf(run);
    EXPECT_EQ(number(json, "reloads"), 2.0) << json;
    EXPECT_EQ(number(json, "reloads_refused"), 1.0) << json;
    EXPECT_EQ(number(json, "errors"), 0.0) << json;
    EXPECT_NE(json.find("\"stopped_by\": \"SIGTERM\""), std::string::npos) << json;
    // Nothing moves (no drift, no input): the first frame and one after each reload are drawn,
    // the other ticks skipped.
    EXPECT_GT(number(json, "frames") + number(json, "skipped"), 10.0) << json;
    EXPECT_GE(number(json, "frames"), 3.0) << json;
}

}  // namespace
}  // namespace vpe::firmware
