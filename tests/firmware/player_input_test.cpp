// SPDX-License-Identifier: MIT
// vpe-player with inputs, end to end on the real binary: --check, replayed knob edges (with
// bounce), OSC messages and camera frames through the real decoders, absent hardware logged
// once, and a bundle reloaded on SIGHUP or when its file is replaced (a bad one refused while
// the old keeps playing); the lamp mapped by the bundle's camera, and following a reloaded
// bundle's. Runs that render SKIP without EGL.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "vpe/firmware/player/player.h"
#include "vpe/firmware/tracking/camera_lamp_model.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/pinhole_camera.h"

#include "player_fixture.h"
#include "replay_script.h"

namespace vpe::firmware {
namespace {

using namespace vpe::firmware::testing;
using vpe::testing::ReplayScript;

// Asks condition every 20 ms until it holds (true) or bound has passed (false).
template <typename Condition>
bool pollUntil(const Condition& condition, std::chrono::milliseconds bound) {
    constexpr std::chrono::milliseconds kPoll(20);
    for (std::chrono::milliseconds waited(0); waited < bound; waited += kPoll) {
        if (condition()) {
            return true;
        }
        std::this_thread::sleep_for(kPoll);
    }
    return false;
}

// The boards' tail: no idle drift and no pacing, so the light moves by the inputs alone and
// frames come as fast as they draw.
const std::string kNoDriftUnpaced = "[idle]\nenabled = false\n[render]\nrate = 0\n";

// replayBoardInputs' knobs and camera (switched on: absent here); no smoothing and no drift,
// so the final light is exact.
const std::string kInputs = vpe::testing::replayBoardInputs(true) + R"(
[light]
azimuth = [-90, 90]
elevation = [0, 80]
initial_azimuth = 0
initial_elevation = 30
smoothing_s = 0
)" + kNoDriftUnpaced;

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
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    ReplayScript script;
    // 10 clicks clockwise and 3 back, bouncing: +14°; then 5 clicks up: +5°.
    double t = script.knobTurn(17, 18, 0.05, 10, 0.02, 0.002, 2);
    t = script.knobTurn(17, 18, t, -3, 0.02, 0.002, 3);
    t = script.knobTurn(22, 23, t, 5, 0.02);
    script.buttonPress(27, t, 0.05);
    // The player on a script, written to folder_/name first, with its --json report.
    const auto replay = [&](const ReplayScript& replayed, const std::string& name) {
        const fs::path file = folder_ / name;
        replayed.write(file);
        return play({"--board", board_.string(), "--bundle", bundle_.string(), "--replay",
                     file.string(), "--json"});
    };
    PlayerRun run = replay(script, "knobs.jsonl");
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
    run = replay(mixed, "osc.jsonl");
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
    run = replay(camera, "camera.jsonl");
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
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
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

    // Counted in ticks, not seconds: the turn is over within 0.11 s of the loop's start, 100
    // ticks at 200 Hz take at least 0.5 s however long a drawn frame takes (under qemu-user,
    // up to 0.3 s), and every tick after the last detent is skipped.
    ReplayScript script;
    script.knobTurn(17, 18, 0.05, 3, 0.02);  // three detents: three new lights
    const fs::path knobs = folder_ / "turn.jsonl";
    script.write(knobs);
    run = play({"--board", board.string(), "--bundle", bundle_.string(), "--replay", knobs.string(),
                "--frames", "100", "--json"});
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
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
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
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
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
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board =
        writeFile("paced.toml", "[display]\nbackend = \"headless\"\n[render]\nrate = 30\n");
    // The first frame, written out, says the player is drawing: only then may the bundle
    // change (a busy machine once started the player so late that all three reloads came
    // before its first frame, which then drew them as one).
    const fs::path frames = folder_ / "frames";
    // The light log has a line per tick (flushed every 30): the waits below count ticks, not
    // seconds, so a slow machine (qemu-user: a drawn frame up to 0.3 s) waits as long as it must.
    const fs::path ticks = folder_ / "ticks.jsonl";
    const pid_t pid =
        spawn({"--board", board.string(), "--bundle", bundle_.string(), "--json", "--out",
               frames.string(), "--every", "1000000", "--light-log", ticks.string()});
    ASSERT_GT(pid, 0);
    // A bound on failure only (30 s): a slow machine waits longer.
    const auto waitUntil = [](const auto& condition) {
        return pollUntil(condition, std::chrono::seconds(30));
    };
    const auto waitFor = [&](const std::string& needle) {
        return waitUntil([&] { return spawnedErr().find(needle) != std::string::npos; });
    };
    const auto tickCount = [&] {
        std::ifstream in(ticks);
        return std::count(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>(),
                          '\n');
    };
    // `count` more ticks logged: at least count − 30 of them happened since the call.
    const auto waitTicks = [&](long count) {
        const long from = tickCount();
        return waitUntil([&] { return tickCount() >= from + count; });
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
    // Two reloads within one tick draw one frame: let the player draw after this one first.
    EXPECT_TRUE(waitTicks(36)) << spawnedErr();
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(waitFor("reloaded (SIGHUP)")) << spawnedErr();
    // A dozen ticks and more after the reloads.
    EXPECT_TRUE(waitTicks(45)) << spawnedErr();
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

// ---- the lamp mapped by the bundle's camera (format 1.3) --------------------------------------

// A camera high in front of the vase, looking down at it, with a little barrel distortion; the
// same camera moved for the reloaded bundle.
proto::PinholeCamera installationCamera(double x = 0.25) {
    proto::PinholeCamera camera =
        proto::cameraLookingAt(640, 480, 60.0, {x, 1.1, 0.9}, {0.0, 0.075, 0.0});
    camera.distortion = {-0.08, 0.02, 0.0, 0.0, 0.0};
    return camera;
}

std::string bundleWith(const std::optional<proto::PinholeCamera>& camera) {
    renderer::testing::GlesBundleSpec spec;
    spec.camera = camera;
    const std::vector<std::byte> bytes = renderer::testing::buildGlesTestBundle(spec);
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// The board: the camera switched on (absent here) with no table, the lamp 0.4 m from the vase.
const std::string kCameraModelBoard = R"([display]
backend = "headless"
[camera]
enabled = true
size = "320x240"
hold_s = 0.3
lamp_distance_m = 0.4
[light]
smoothing_s = 0
)" + kNoDriftUnpaced;

// Where the lamp at (azimuth, elevation) on the 0.4 m sphere shows in the 320 × 240 stream.
proto::Vec2d streamPixel(const proto::PinholeCamera& camera, const fs::path& bundle,
                         double azimuthDeg, double elevationDeg) {
    const proto::BundleFile file = proto::BundleFile::open(bundle);
    const std::array<double, 3> p =
        Player::sphereOf(file.view()).toPosition({azimuthDeg, elevationDeg, 0.4});
    const proto::Vec2d pixel = *proto::projectToPixel(camera, {p[0], p[1], p[2]});
    return {(pixel.x + 0.5) * 0.5 - 0.5, (pixel.y + 0.5) * 0.5 - 0.5};
}

TEST_F(PlayerInputTest, MapsTheLampWithTheBundlesCameraOrRefusesTheBoard) {
    const fs::path board = writeFile("camera.toml", kCameraModelBoard);
    const fs::path withCamera = writeFile("camera.vpeb", bundleWith(installationCamera()));

    const PlayerRun checked =
        play({"--board", board.string(), "--bundle", withCamera.string(), "--check"});
    EXPECT_EQ(checked.status, 0) << checked.err;
    EXPECT_NE(checked.out.find("camera: auto, 320x240, the lamp mapped by the bundle's camera "
                               "(640x480 scaled to 320x240; lamp sphere 0.4 m, the camera "
                               "outside it)"),
              std::string::npos)
        << checked.out;
    EXPECT_NE(checked.out.find("2 presets, camera 640x480"), std::string::npos) << checked.out;
    const PlayerRun unbundled = play({"--board", board.string(), "--check"});
    EXPECT_EQ(unbundled.status, 0) << unbundled.err;
    EXPECT_NE(unbundled.out.find("no calibration table: the lamp needs the bundle's camera"),
              std::string::npos)
        << unbundled.out;

    // Neither a table nor a camera: --check and start-up both refuse the board, one line.
    const std::string absent =
        "camera.toml:camera.calibration: absent, and the bundle carries "
        "no camera (bake it from a scan or a calibration with cam_K)";
    expectOneLineError(play({"--board", board.string(), "--bundle", bundle_.string(), "--check"}),
                       absent);
    // A calibration of another shape than the stream's names the size.
    proto::PinholeCamera wide = installationCamera();
    wide.width = 1920;
    wide.height = 1080;
    const fs::path wideBundle = writeFile("wide.vpeb", bundleWith(wide));
    expectOneLineError(
        play({"--board", board.string(), "--bundle", wideBundle.string(), "--check"}),
        "camera.toml:camera.size: the stream's 320x240 (aspect 1.333) is not the camera "
        "calibration's 1920x1080 (aspect 1.778) scaled");

    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    // Start-up opens the display and the bundle first, then refuses the board the same way.
    expectOneLineError(
        play({"--board", board.string(), "--bundle", bundle_.string(), "--frames", "1"}), absent);
    // The lamp held at azimuth 25°, elevation 40°, then beside the sphere (a ray that misses).
    const proto::Vec2d lamp = streamPixel(installationCamera(), withCamera, 25.0, 40.0);
    ReplayScript script;
    for (int frame = 0; frame < 10; ++frame) {
        script.cameraLamp(0.05 + frame * 0.02, lamp.x, lamp.y, 2.5);
    }
    for (int frame = 0; frame < 3; ++frame) {
        script.cameraLamp(0.3 + frame * 0.02, 8.0, 8.0, 2.5);
    }
    const fs::path replay = folder_ / "lamp.jsonl";
    script.write(replay);
    const PlayerRun run = play({"--board", board.string(), "--bundle", withCamera.string(),
                                "--replay", replay.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const std::string json = jsonOf(run);
    EXPECT_EQ(number(json, "camera"), 10.0) << json;
    EXPECT_NEAR(number(json, "azimuth"), 25.0, 0.3) << json;
    EXPECT_NEAR(number(json, "elevation"), 40.0, 0.3) << json;
    EXPECT_EQ(number(json, "camera.ray_misses_sphere"), 3.0) << json;
}

TEST_F(PlayerInputTest, TheLampFollowsTheCameraOfAReloadedBundle) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board = writeFile("camera.toml", kCameraModelBoard);
    const fs::path scene = writeFile("scene-camera.vpeb", bundleWith(installationCamera()));
    // The lamp stays at one pixel, frame after frame (the replay loops).
    const proto::Vec2d lamp = streamPixel(installationCamera(), scene, 25.0, 40.0);
    ReplayScript script;
    for (int frame = 0; frame < 60; ++frame) {
        script.cameraLamp(frame * 0.05, lamp.x, lamp.y, 2.5);
    }
    const fs::path replay = folder_ / "still.jsonl";
    script.write(replay);
    const fs::path frames = folder_ / "frames";
    const pid_t pid =
        spawn({"--board", board.string(), "--bundle", scene.string(), "--replay", replay.string(),
               "--replay-loop", "--json", "--out", frames.string(), "--every", "1000000"});
    ASSERT_GT(pid, 0);
    const auto waitUntil = [](const auto& condition) {
        return pollUntil(condition, std::chrono::seconds(6));
    };
    ASSERT_TRUE(waitUntil([&] { return fs::exists(frames / "frame_00000.ppm"); })) << spawnedErr();
    // The camera moved 0.3 m sideways and calibrated again: the same pixel is another direction.
    writeFile("next.tmp", bundleWith(installationCamera(-0.05)));
    fs::rename(folder_ / "next.tmp", scene);
    EXPECT_TRUE(waitUntil([&] {
        return spawnedErr().find("camera: the lamp follows the bundle's camera") !=
               std::string::npos;
    })) << spawnedErr();
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    ::kill(pid, SIGTERM);
    const PlayerRun run = finish(pid);
    EXPECT_EQ(run.status, 0) << run.err;
    const std::string json = jsonOf(run);
    EXPECT_EQ(number(json, "reloads"), 1.0) << json;
    // Where the new camera puts that pixel, on the new bundle's sphere.
    const proto::BundleFile file = proto::BundleFile::open(scene);
    const CameraLampModel moved(installationCamera(-0.05), 320, 240, Player::sphereOf(file.view()),
                                0.4);
    const std::optional<LightDirection> expected = moved.direction(lamp.x, lamp.y);
    ASSERT_TRUE(expected.has_value());
    EXPECT_GT(std::abs(expected->azimuthDeg - 25.0), 5.0);  // the move matters
    EXPECT_NEAR(number(json, "azimuth"), expected->azimuthDeg, 0.3) << json;
    EXPECT_NEAR(number(json, "elevation"), expected->elevationDeg, 0.3) << json;
}

}  // namespace
}  // namespace vpe::firmware
