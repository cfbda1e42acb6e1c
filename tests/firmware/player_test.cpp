// SPDX-License-Identifier: MIT
// vpe-player end to end: a small bundle (the GLES tests' vase, 160 × 120) played headless for 5
// frames with --json and --out; bad arguments, board files, bundles and an absent KMS display
// end with one line on stderr and exit status 2. The headless run SKIPs without EGL.
#include <chrono>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "player_fixture.h"

namespace vpe::firmware {
namespace {

using namespace vpe::firmware::testing;

TEST_F(PlayerTest, PlaysFiveFramesHeadlessWithJson) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path frames = folder_ / "frames";
    const PlayerRun run =
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--frames", "5",
              "--size", "160x120", "--json", "--out", frames.string(), "--every", "2"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err;
    // stdout ends with the JSON object, on its own line.
    const std::size_t open = run.out.rfind("\n{");
    ASSERT_NE(open, std::string::npos) << run.out;
    const std::string json = run.out.substr(open + 1);
    EXPECT_EQ(json.back(), '\n');
    EXPECT_EQ(json[json.size() - 2], '}');
    for (const char* key : {"\"frames\": 5", "\"fps\": ", "\"frame_ms\": {", "\"p50\": ",
                            "\"p99\": ", "\"width\": 160", "\"height\": 120", "\"written\": 3"}) {
        EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
    }
    // Frames 0, 2, 4 as PPM, and nothing half-written beside them.
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(frames)) {
        names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    ASSERT_EQ(names,
              (std::vector<std::string>{"frame_00000.ppm", "frame_00002.ppm", "frame_00004.ppm"}));
    const std::string ppm = readAll(frames / "frame_00002.ppm");
    const std::string header = "P6\n160 120\n255\n";
    ASSERT_EQ(ppm.size(), header.size() + 160 * 120 * 3);
    EXPECT_EQ(ppm.substr(0, header.size()), header);
    std::size_t lit = 0;
    for (std::size_t i = header.size(); i < ppm.size(); ++i) {
        lit += ppm[i] != 0 ? 1 : 0;
    }
    EXPECT_GT(lit, 160u * 120u / 10) << "the vase should be lit";
    // The light moves: frames differ.
    EXPECT_NE(readAll(frames / "frame_00000.ppm"), ppm);
}

// --light-log: one line per frame tick, the presentation time on the wall clock (a frame period
// ahead of when the frame was begun), so that the nodes of a show can be compared.
TEST_F(PlayerTest, WritesALightLogLineForEveryFrame) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path log = folder_ / "light.jsonl";
    const auto before = std::chrono::system_clock::now();
    const PlayerRun run = play({"--board", headless_.string(), "--bundle", bundle_.string(),
                                "--frames", "8", "--rate", "60", "--light-log", log.string()});
    const auto after = std::chrono::system_clock::now();
    ASSERT_EQ(run.status, 0) << run.err;
    std::istringstream lines(readAll(log));
    std::string line;
    long long previous = 0;
    int count = 0;
    const auto micros = [](std::chrono::system_clock::time_point t) {
        return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
    };
    while (std::getline(lines, line)) {
        ++count;
        ASSERT_EQ(line.substr(0, 9), "{\"t_us\": ") << line;
        const long long t = std::stoll(line.substr(9));
        EXPECT_GT(t, previous) << line;
        EXPECT_GT(t, micros(before)) << line;
        EXPECT_LT(t, micros(after) + 17'000) << line;  // at most a frame period ahead
        previous = t;
        EXPECT_NE(line.find("\"azimuth\": "), std::string::npos) << line;
        EXPECT_NE(line.find("\"active\": \"idle\", \"drawn\": true}"), std::string::npos) << line;
    }
    EXPECT_EQ(count, 8);
    expectOneLineError(play({"--board", headless_.string(), "--bundle", bundle_.string(),
                             "--frames", "1", "--light-log", (folder_ / "no/such/dir/x").string()}),
                       "no/such/dir/x: cannot write (No such file or directory)");
}

TEST_F(PlayerTest, RefusesBadArguments) {
    expectOneLineError(play({"--bundle", bundle_.string()}), "--board: missing");
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--frames", "-1"}),
        "--frames: expected a positive integer, got \"-1\"");
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--size", "160"}),
        "--size: expected WxH");
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--fast"}),
        "--fast: unknown argument");
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--light-log", ""}),
        "--light-log: expected a file, got \"\"");
}

TEST_F(PlayerTest, RefusesBadBoardFiles) {
    const fs::path bad = writeFile("bad.toml", "[display]\nbackend = \"kms\"\nmode = \"big\"\n");
    expectOneLineError(play({"--board", bad.string(), "--bundle", bundle_.string()}),
                       bad.string() + ":display.mode: expected");
    const fs::path unknown =
        writeFile("unknown.toml", "[display]\nbackend = \"headless\"\nfps = 60\n");
    expectOneLineError(play({"--board", unknown.string(), "--bundle", bundle_.string()}),
                       unknown.string() + ":display.fps: unknown key");
    expectOneLineError(
        play({"--board", (folder_ / "none.toml").string(), "--bundle", bundle_.string()}),
        "none.toml: cannot read board file (no such file)");
}

TEST_F(PlayerTest, RefusesMissingAndCorruptBundles) {
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", (folder_ / "missing.vpeb").string()}),
        "missing.vpeb");
    std::string corrupt = bundleBytes_;
    corrupt[corrupt.size() - 7] = static_cast<char>(corrupt[corrupt.size() - 7] ^ 0x5a);
    const fs::path flipped = writeFile("flipped.vpeb", corrupt);
    expectOneLineError(play({"--board", headless_.string(), "--bundle", flipped.string()}),
                       "flipped.vpeb: ");
    const fs::path truncated = writeFile("truncated.vpeb", bundleBytes_.substr(0, 100));
    expectOneLineError(play({"--board", headless_.string(), "--bundle", truncated.string()}),
                       "truncated.vpeb: ");
    const fs::path text = writeFile("text.vpeb", "not a bundle at all\n");
    expectOneLineError(play({"--board", headless_.string(), "--bundle", text.string()}),
                       "text.vpeb: ");
}

TEST_F(PlayerTest, RefusesASizeOtherThanTheProjectors) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    expectOneLineError(
        play({"--board", headless_.string(), "--bundle", bundle_.string(), "--size", "320x240"}),
        "--size: 320x240 differs from the bundle's projector 160x120");
}

TEST_F(PlayerTest, ReportsAnAbsentKmsDisplay) {
    if (fs::exists("/dev/dri/card0")) {
        GTEST_SKIP() << "/dev/dri/card0 exists here";
    }
    const fs::path kms =
        writeFile("kms.toml", "[display]\nbackend = \"kms\"\ndevice = \"/dev/dri/card0\"\n");
    const PlayerRun run = play({"--board", kms.string(), "--bundle", bundle_.string()});
    expectOneLineError(run, "/dev/dri/card0: no such device (KMS display unavailable)");
    EXPECT_EQ(run.err, "vpe-player: /dev/dri/card0: no such device (KMS display unavailable)\n");
    const fs::path out = folder_ / "frames";
    expectOneLineError(
        play({"--board", kms.string(), "--bundle", bundle_.string(), "--out", out.string()}),
        "--out: frames are read back only on the headless display");
}

}  // namespace
}  // namespace vpe::firmware
