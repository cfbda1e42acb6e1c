// SPDX-License-Identifier: MIT
// vpe-player --scan end to end, headless with the simulated camera on a small installation (a
// ball before a wall; projector 320 × 180, camera 320 × 240): the manifest, every image equal
// to what ProcamSimulator renders for its pattern (what the display showed reached the
// simulated projector exactly), a previous scan replaced whole; stale captures retried and
// counted (the radiometric capture after the scan keeping the longer wait), retries running out
// (exit 1, nothing written); and bad input (exit 2, one line). The radiometric capture itself:
// scan_radiometry_test.cpp. The runs SKIP without headless EGL.
#include <algorithm>
#include <csignal>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/proto/structured_light.h"
#include "vpe/renderer/procam/procam_simulator.h"
#include "vpe/renderer/procam/scene_file.h"

#include "scan_fixture.h"

namespace vpe::firmware {
namespace {

using namespace vpe::firmware::testing;

TEST_F(ScanTest, CapturesEveryPatternAsTheSimulatorRendersIt) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    // A previous scan in OUT is replaced whole (its stray file goes with it).
    fs::create_directories(out_);
    std::ofstream(out_ / proto::kScanManifestName) << "{}";
    std::ofstream(out_ / "stray.txt") << "from the previous scan";

    // The default sequence; the radiometric capture after it on the shortest ladder (two levels
    // per primary: its default one is scan_radiometry_test.cpp's).
    const fs::path board = scanBoard("latency_ms = 0\nradiometry_levels = 2\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err;
    EXPECT_EQ(run.out.rfind("scan: ", 0), 0u) << run.out;

    const proto::ScanManifest manifest = proto::readScanManifest(out_);
    expectWrittenBySimulatedPlayer(manifest, manifest.patterns, installation_);
    EXPECT_EQ(manifest.patterns.phasePeriod, 32);
    EXPECT_EQ(manifest.patterns.phaseSteps, 8);

    const proto::StructuredLightSequence sequence(manifest.patterns);
    const std::vector<proto::PatternSpec>& patterns = sequence.patterns();
    ASSERT_EQ(manifest.images.size(), patterns.size());
    // The radiometric capture's folder beside the patterns (scan_radiometry_test.cpp).
    std::set<std::string> expected{proto::kScanManifestName, proto::kRadiometryFolderName};
    for (std::size_t i = 0; i < patterns.size(); ++i) {
        EXPECT_EQ(manifest.images[i].file, proto::scanImageName(i, patterns[i]));
        EXPECT_EQ(manifest.images[i].pattern, patterns[i].name());
        EXPECT_EQ(manifest.images[i].attempts, 1) << patterns[i].name();
        expected.insert(manifest.images[i].file);
    }
    const std::vector<std::string> names = namesIn(out_);
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), expected);
    expectNoTemporaryFolders();

    // Every image is the simulator's frame of its pattern: capture i is frame i.
    const renderer::procam::SceneFile scene =
        renderer::procam::readSceneFile(installation_.sceneFile);
    const renderer::procam::ProcamSimulator simulator(scene.scene, scene.camera);
    std::vector<std::uint8_t> codes(320 * 180);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < patterns.size(); ++i) {
        sequence.render(patterns[i], codes);
        const renderer::procam::CameraFrame truth = simulator.expose(simulator.radiance(codes), i);
        const Pnm image = readPnm(out_ / manifest.images[i].file);
        ASSERT_EQ(image.width, 320) << manifest.images[i].file;
        ASSERT_EQ(image.height, 240);
        EXPECT_EQ(image.maxValue, 255);
        if (image.samples != truth.samples) {
            ++differing;
            ADD_FAILURE() << manifest.images[i].file << " differs from the simulator's frame";
        }
    }
    EXPECT_EQ(differing, 0u);

    const nlohmann::json report = reportOf(run);
    ASSERT_TRUE(report.is_object()) << run.out;
    EXPECT_EQ(report["patterns"], patterns.size());
    EXPECT_EQ(report["captures"], patterns.size());
    EXPECT_EQ(report["retried"], 0);
    EXPECT_EQ(report["camera"]["source"], manifest.camera.source);
    EXPECT_EQ(report["projector"]["width"], 320);
    EXPECT_GT(report["lit_fraction"].get<double>(), 0.2);
    EXPECT_GT(report["noise_sigma"].get<double>(), 0.0);
    EXPECT_EQ(report["radiometry"]["captured"], true);
    for (const char* key : {"rejected", "platform", "latency_ms", "wait_ms", "simulated_latency_ms",
                            "setup_ms", "capture_ms", "radiometry", "scan_seconds", "seconds"}) {
        EXPECT_TRUE(report.contains(key)) << key;
    }
}

TEST_F(ScanTest, TenBitCameraWritesSixteenBitImages) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    installation_ = writeScanInstallation(folder_, 10);
    // The shortest sequence: a coarse period and three steps; the shortest radiometric ladder.
    const fs::path board =
        scanBoard("latency_ms = 0\nphase_period = 64\nphase_steps = 3\nradiometry_levels = 2\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string()});
    ASSERT_EQ(run.status, 0) << run.err;
    const proto::ScanManifest manifest = proto::readScanManifest(out_);
    EXPECT_EQ(manifest.camera.bits, 10);
    EXPECT_EQ(manifest.patterns.phasePeriod, 64);
    EXPECT_EQ(manifest.patterns.phaseSteps, 3);
    const Pnm white = readPnm(out_ / manifest.images[0].file);
    EXPECT_EQ(white.maxValue, 1023);
    EXPECT_GT(*std::max_element(white.samples.begin(), white.samples.end()), 255);
}

TEST_F(ScanTest, RetriesStaleCapturesAndKeepsTheLongerWait) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    // The projector takes 300 ms, the board waits 0: the first white and black are captured
    // before they are shown (both black: nothing is lit); the retry waits 350 ms, and so does
    // every pattern after it, and every flat field of the radiometric capture after them (the
    // shortest ladder: two levels per primary).
    const fs::path board = scanBoard(
        "latency_ms = 0\nretries = 2\nretry_wait_ms = 350\nsimulated_latency_ms = 300\n"
        "phase_period = 64\nphase_steps = 3\nradiometry_levels = 2\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    // One line: the wait the projector needed.
    EXPECT_NE(run.err.find("scan: the projector needed 350 ms after a pattern"), std::string::npos)
        << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    const proto::ScanManifest manifest = proto::readScanManifest(out_);
    ASSERT_GE(manifest.images.size(), 3u);
    EXPECT_EQ(manifest.projectorLatencyMs, 350.0);  // the wait the captures used
    EXPECT_EQ(manifest.images[0].attempts, 2);
    EXPECT_EQ(manifest.images[1].attempts, 2);
    for (std::size_t i = 2; i < manifest.images.size(); ++i) {
        EXPECT_EQ(manifest.images[i].attempts, 1) << manifest.images[i].pattern;
    }
    const nlohmann::json report = reportOf(run);
    EXPECT_EQ(report["retried"], 2);
    EXPECT_EQ(report["captures"], manifest.images.size() + 2);
    EXPECT_EQ(report["rejected"]["not_lit"], 1);
    EXPECT_EQ(report["wait_ms"], 350.0);
    EXPECT_EQ(report["latency_ms"], 0.0);

    const proto::RadiometryManifest radiometry =
        proto::readRadiometryManifest(out_ / proto::kRadiometryFolderName);
    EXPECT_EQ(radiometry.projectorLatencyMs, 350.0);
    EXPECT_EQ(radiometry.images.size(), 8u);  // black, white, 2 levels × 3 primaries
    for (const proto::RadiometryImage& image : radiometry.images) {
        EXPECT_EQ(image.attempts, 1) << image.pattern;
    }
    EXPECT_EQ(report["radiometry"]["captures"], 8);
    EXPECT_EQ(report["radiometry"]["retried"], 0);
}

TEST_F(ScanTest, StopsWhenRetriesRunOutAndWritesNothing) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board =
        scanBoard("latency_ms = 0\nretries = 1\nretry_wait_ms = 50\nsimulated_latency_ms = 2000\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string()});
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.err.rfind("vpe-player: scan: black: white − black reaches 5.0% of full scale on "
                            "0.0% of the camera's pixels",
                            0),
              0u)
        << run.err;
    EXPECT_NE(run.err.find("(2 captures, the last 50 ms after the pattern"), std::string::npos)
        << run.err;
    EXPECT_FALSE(fs::exists(out_));
    expectNoTemporaryFolders();
}

TEST_F(ScanTest, StopsOnSigintAndWritesNothing) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    // Black stays up for 2 s before the first pattern: SIGINT arrives during it.
    const fs::path board = scanBoard("settle_ms = 2000\nlatency_ms = 0\n");
    const pid_t pid = spawn({"--board", board.string(), "--scan", out_.string()});
    ASSERT_GT(pid, 0);
    // Once the temporary folder exists the signals are already taken by the scan.
    bool started = false;
    for (int i = 0; i < 500 && !started; ++i) {
        started = fs::exists(out_.parent_path()) && !namesIn(out_.parent_path()).empty();
        ::usleep(10'000);
    }
    ASSERT_TRUE(started) << spawnedErr();
    ::kill(pid, SIGINT);
    const PlayerRun run = finish(pid);
    EXPECT_EQ(run.status, 1) << run.err;
    EXPECT_EQ(run.err, "vpe-player: scan: stopped by SIGINT; nothing written\n");
    EXPECT_FALSE(fs::exists(out_));
    expectNoTemporaryFolders();
}

TEST_F(ScanTest, RefusesBoardsThatCannotScan) {
    const fs::path noScan = writeFile("no-scan.toml", "[display]\nbackend = \"headless\"\n");
    expectOneLineError(play({"--board", noScan.string(), "--scan", out_.string()}),
                       noScan.string() + ":scan: missing (a [scan] section");
    const fs::path noCamera =
        writeFile("no-camera.toml", "[display]\nbackend = \"kms\"\n[scan]\nlatency_ms = 100\n");
    expectOneLineError(
        play({"--board", noCamera.string(), "--scan", out_.string()}),
        noCamera.string() + ":camera: missing; the scan photographs with the lamp's");
    const fs::path disabled = writeFile(
        "disabled.toml",
        "[display]\nbackend = \"kms\"\n[camera]\nenabled = false\n[scan]\nlatency_ms = 100\n");
    expectOneLineError(play({"--board", disabled.string(), "--scan", out_.string()}),
                       disabled.string() + ":camera.enabled: false; the scan photographs");
    const fs::path headless = writeFile(
        "headless-camera.toml",
        "[display]\nbackend = \"headless\"\n[camera]\nenabled = true\n[scan]\nlatency_ms = 1\n");
    expectOneLineError(play({"--board", headless.string(), "--scan", out_.string()}),
                       headless.string() +
                           ":display.backend: \"headless\" shows the patterns to "
                           "no projector");
    const fs::path kmsSimulated =
        writeFile("kms-simulated.toml",
                  "[display]\nbackend = \"kms\"\n[scan]\nsimulate = \"installation.toml\"\n");
    expectOneLineError(play({"--board", kmsSimulated.string(), "--scan", out_.string()}),
                       kmsSimulated.string() +
                           ":scan.simulate: the simulated camera needs the "
                           "headless display");
    const fs::path noScene =
        writeFile("no-scene.toml",
                  "[display]\nbackend = \"headless\"\n[scan]\nsimulate = \"elsewhere.toml\"\n");
    expectOneLineError(play({"--board", noScene.string(), "--scan", out_.string()}),
                       (folder_ / "elsewhere.toml").string());
    EXPECT_FALSE(fs::exists(out_));
    expectNoTemporaryFolders();
}

TEST_F(ScanTest, ReportsAnAbsentCameraInOneLine) {
    const fs::path board =
        writeFile("camera.toml",
                  "[display]\nbackend = \"kms\"\n[camera]\nenabled = true\n[scan]\n"
                  "latency_ms = 100\ncamera_size = \"640x480\"\n");
    ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string()});
    if (run.err.find("camera: no camera found") == std::string::npos) {
        GTEST_SKIP() << "a camera is present here: " << run.err;
    }
    expectOneLineError(run, "camera: no camera found (libcamera lists none)");
    EXPECT_EQ(run.err, "vpe-player: camera: no camera found (libcamera lists none)\n");
    EXPECT_FALSE(fs::exists(out_));
    expectNoTemporaryFolders();
}

TEST_F(ScanTest, CheckDescribesTheScan) {
    const fs::path board = scanBoard("latency_ms = 40\nretries = 2\n");
    const PlayerRun run = play({"--board", board.string(), "--check"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_NE(run.out.find("  scan: simulated camera " + installation_.sceneFile.string() +
                           "; latency 40 ms, 2 retries, period 32, 8 steps\n"),
              std::string::npos)
        << run.out;
    const PlayerRun none = play({"--board", headless_.string(), "--check"});
    EXPECT_NE(none.out.find("  scan: none (no [scan] section)\n"), std::string::npos) << none.out;
}

TEST_F(ScanTest, RefusesBadScanKeys) {
    const auto refused = [this](const std::string& keys, const std::string& needle) {
        const fs::path board = scanBoard(keys);
        expectOneLineError(play({"--board", board.string(), "--scan", out_.string()}),
                           board.string() + ":" + needle);
    };
    refused("fps = 30\n", "scan.fps: unknown key");
    refused("latency_ms = -1\n", "scan.latency_ms: expected a number in [0, 10000], got -1");
    refused("retries = 2.5\n", "scan.retries: expected an integer");
    refused("phase_period = 48\n", "scan.phase_period: expected a power of two in 8…1024, got 48");
    refused("phase_steps = 2\n", "scan.phase_steps: expected an integer in 3…64, got 2");
    refused("camera_size = \"big\"\n", "scan.camera_size: expected \"WxH\"");
    refused("colour_gains = [1.5]\n", "scan.colour_gains: expected [red, blue] numbers");
    refused("tolerance = 1\n", "scan.tolerance: expected a number in [0, 1), got 1");
    // The sequence's own limits: a period longer than the projector's height.
    refused("phase_period = 512\n", "scan.phase_period: ");
    const fs::path real = writeFile(
        "real.toml",
        "[display]\nbackend = \"kms\"\n[camera]\nenabled = true\n[scan]\nsimulated_latency_ms = "
        "10\n");
    expectOneLineError(play({"--board", real.string(), "--scan", out_.string()}),
                       real.string() + ":scan.simulated_latency_ms: only with scan.simulate");
    EXPECT_FALSE(fs::exists(out_));
}

TEST_F(ScanTest, RefusesAnOutThatIsNotAScanFolder) {
    const fs::path board = scanBoard("latency_ms = 0\n");
    const fs::path file = writeFile("notes.txt", "keep me");
    expectOneLineError(play({"--board", board.string(), "--scan", file.string()}),
                       file.string() + ": exists and is not a folder");
    EXPECT_EQ(readAll(file), "keep me");
    const fs::path other = folder_ / "photos";
    fs::create_directories(other);
    std::ofstream(other / "holiday.jpg") << "not a scan";
    expectOneLineError(play({"--board", board.string(), "--scan", other.string()}),
                       other.string() + ": exists and is not a scan folder (no scan.json)");
    EXPECT_EQ(namesIn(other), std::vector<std::string>{"holiday.jpg"});
}

TEST_F(ScanTest, RefusesArgumentsThatPlayABundle) {
    const fs::path board = scanBoard("latency_ms = 0\n");
    expectOneLineError(
        play({"--board", board.string(), "--scan", out_.string(), "--bundle", bundle_.string()}),
        "--bundle: not used by --scan");
    expectOneLineError(play({"--board", board.string(), "--scan", out_.string(), "--frames", "3"}),
                       "--frames: not used by --scan");
    expectOneLineError(play({"--board", board.string(), "--scan"}), "--scan: missing value");
}

TEST_F(ScanTest, RefusesASizeOtherThanTheSimulatedProjector) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board = scanBoard("latency_ms = 0\n");
    expectOneLineError(
        play({"--board", board.string(), "--scan", out_.string(), "--size", "640x360"}),
        "--size: 640x360 differs from the simulated projector 320x180");
    EXPECT_FALSE(fs::exists(out_));
}

}  // namespace
}  // namespace vpe::firmware
