// SPDX-License-Identifier: MIT
// vpe-player --scan's radiometric capture, end to end, headless with the simulated camera on the
// scan tests' installation (a plaster ball before a wall; projector 320 × 180, camera 320 ×
// 240): after the patterns, OUT/radiometry/ holds radiometry.json that proto's reader accepts
// and one RGB PPM of the camera's size per flat field, in the sequence's order whatever the
// capture's; on the ball white is brighter than black, each primary's ladder brightens its own
// channel, red lights red most; the images are the simulator's colour frames (the flat fields
// reached the projector in RGB). A gamma camera brackets the ramp at the exposures asked for; a
// 10-bit gamma camera and `[scan] radiometry = false` write the scan without it. The runs SKIP
// without headless EGL.
#include <cmath>
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
namespace procam = renderer::procam;

// ScanTest's fixture under its own name: a ctest entry of its own (cmake/VpeTests.cmake groups
// a suite's quick tests in one process), so that the arm64 run under qemu, where the scans
// take minutes, spreads the two suites over its cores.
class ScanRadiometryTest : public ScanTest {};

// The camera pixels that see the ball where the projector lights it.
std::vector<std::size_t> ballPixels(const procam::SceneFile& scene) {
    const procam::ProcamSimulator simulator(scene.scene, scene.camera);
    const procam::CameraTruth truth = simulator.cameraTruth();
    const double radius = 0.07;  // scan_installation.cpp's ball, about (0, radius, 0)
    const proto::Vec3d centre = scene.camera.camera.toCamera({0, radius, 0});
    std::vector<std::size_t> pixels;
    for (std::size_t p = 0; p < truth.projectorX.size(); ++p) {
        const double dx = double(truth.pointCamera[3 * p]) - centre.x,
                     dy = double(truth.pointCamera[3 * p + 1]) - centre.y,
                     dz = double(truth.pointCamera[3 * p + 2]) - centre.z;
        if (!std::isnan(truth.projectorX[p]) &&
            std::sqrt(dx * dx + dy * dy + dz * dz) < radius + 0.002) {
            pixels.push_back(p);
        }
    }
    return pixels;
}

double meanOf(const Pnm& image, const std::vector<std::size_t>& pixels, int channel) {
    double sum = 0;
    for (const std::size_t p : pixels) {
        sum += image.samples[3 * p + static_cast<std::size_t>(channel)];
    }
    return sum / static_cast<double>(pixels.size());
}

// The projector levels of `field`, as the display read back gives them to the simulator.
renderer::RgbImage levelsOf(const proto::FlatField& field, int width, int height) {
    renderer::RgbImage levels(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::array<std::uint8_t, 3> codes = field.codes(x, width);
            for (std::size_t c = 0; c < 3; ++c) {
                levels.pixel(x, y)[c] = static_cast<float>(codes[c]) / 255.0f;
            }
        }
    }
    return levels;
}

TEST_F(ScanRadiometryTest, CapturesTheRadiometryInColourAfterTheScan) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    // The default ladder after the shortest scan (a coarse period, three steps): the scan's own
    // default sequence is scan_test.cpp's.
    const fs::path board = scanBoard("latency_ms = 0\nphase_period = 64\nphase_steps = 3\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err;
    EXPECT_NE(run.out.find("; radiometry: 50 flat fields, 50 captures (0 retried), response "
                           "linear, 8 bits\n"),
              std::string::npos)
        << run.out;

    const fs::path folder = out_ / proto::kRadiometryFolderName;
    const proto::RadiometryManifest manifest = proto::readRadiometryManifest(folder);
    expectWrittenBySimulatedPlayer(manifest, manifest.fields, installation_);
    EXPECT_EQ(manifest.fields.levels, 16);
    EXPECT_EQ(manifest.camera.channels, 3);
    EXPECT_EQ(manifest.camera.response, proto::CameraResponseKind::kLinear);

    const std::vector<proto::FlatField> fields = proto::radiometrySequence(manifest.fields);
    ASSERT_EQ(fields.size(), 50u);  // black, white, 16 levels × 3 primaries
    ASSERT_EQ(manifest.images.size(), fields.size());
    std::set<std::string> expected{proto::kRadiometryManifestName};
    std::vector<Pnm> images;
    for (std::size_t i = 0; i < fields.size(); ++i) {
        EXPECT_EQ(manifest.images[i].file, proto::radiometryImageName(i, fields[i]));
        EXPECT_EQ(manifest.images[i].attempts, 1) << fields[i].name();
        expected.insert(manifest.images[i].file);
        images.push_back(readPnm(folder / manifest.images[i].file));
        const Pnm& image = images.back();
        ASSERT_EQ(image.channels, 3) << manifest.images[i].file;
        ASSERT_EQ(image.width, 320);
        ASSERT_EQ(image.height, 240);
        EXPECT_EQ(image.maxValue, 255);
    }
    const std::vector<std::string> names = namesIn(folder);
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()), expected);
    expectNoTemporaryFolders();

    const procam::SceneFile scene = procam::readSceneFile(installation_.sceneFile);
    const std::vector<std::size_t> ball = ballPixels(scene);
    ASSERT_GT(ball.size(), 1000u);
    // White brighter than black on the ball, in every channel.
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(meanOf(images[1], ball, c), meanOf(images[0], ball, c) + 60) << "channel " << c;
    }
    EXPECT_LT(meanOf(images[0], ball, 0), 20);
    // Each primary's ladder (written in the sequence's order, captured out of it) brightens its
    // own channel step by step; at full level it outshines the other two.
    for (int channel = 0; channel < 3; ++channel) {
        double previous = -1;
        for (std::size_t i = 0; i < fields.size(); ++i) {
            if (fields[i].kind != proto::FlatFieldKind::kPrimary || fields[i].channel != channel) {
                continue;
            }
            const double mean = meanOf(images[i], ball, channel);
            EXPECT_GT(mean, previous) << fields[i].name();
            previous = mean;
        }
    }
    const Pnm& red = images[static_cast<std::size_t>(17)];  // flat-red-255
    ASSERT_EQ(fields[17].name(), "flat-red-255");
    EXPECT_GT(meanOf(red, ball, 0), 2 * meanOf(red, ball, 1));
    EXPECT_GT(meanOf(red, ball, 0), 2 * meanOf(red, ball, 2));

    // The simulator's colour frames: black and white are the captures after the scan's.
    const proto::ScanManifest scanManifest = proto::readScanManifest(out_);
    const std::size_t first = scanManifest.images.size();
    const procam::ProcamSimulator simulator(scene.scene, scene.camera);
    procam::SimulatedCamera colour = scene.camera;
    colour.monochrome = false;
    for (const std::size_t i : {std::size_t{0}, std::size_t{1}}) {
        const procam::CameraFrame truth =
            simulator.expose(simulator.radiance(levelsOf(fields[i], 320, 180)), first + i, colour);
        EXPECT_EQ(truth.channels, 3);
        EXPECT_TRUE(images[i].samples == truth.samples) << fields[i].name();
    }

    const nlohmann::json report = reportOf(run)["radiometry"];
    ASSERT_TRUE(report.is_object()) << run.out;
    EXPECT_EQ(report["captured"], true);
    EXPECT_EQ(report["out"], folder.string());
    EXPECT_EQ(report["fields"], 50);
    EXPECT_EQ(report["captures"], 50);
    EXPECT_EQ(report["retried"], 0);
    EXPECT_EQ(report["response"], "linear");
    EXPECT_EQ(report["bits"], 8);
    EXPECT_GT(report["lit_fraction"].get<double>(), 0.2);
    for (const char* key : {"rejected", "description", "capture_ms", "seconds"}) {
        EXPECT_TRUE(report.contains(key)) << key;
    }
}

TEST_F(ScanRadiometryTest, BracketsTheRampForACameraOfUnknownResponse) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    installation_ = writeScanInstallation(folder_, 8, procam::CameraResponse::kGamma);
    // The shortest ladder before the ramp (two levels per primary): the bracket is the subject.
    const fs::path board =
        scanBoard("latency_ms = 0\nphase_period = 64\nphase_steps = 3\nradiometry_levels = 2\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string()});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err;

    const fs::path folder = out_ / proto::kRadiometryFolderName;
    const proto::RadiometryManifest manifest = proto::readRadiometryManifest(folder);
    EXPECT_EQ(manifest.camera.response, proto::CameraResponseKind::kUnknown);
    EXPECT_EQ(manifest.camera.bits, 8);
    const std::vector<proto::FlatField> fields = proto::radiometrySequence(manifest.fields);
    ASSERT_EQ(fields.size(), 2u + 3 * 2 + 5);  // and the ramp at 5 stops
    ASSERT_EQ(manifest.images.size(), fields.size());
    std::vector<Pnm> ramps;
    for (std::size_t i = 8; i < fields.size(); ++i) {
        ASSERT_EQ(fields[i].name(), "ramp-e" + std::to_string(i - 8));
        ramps.push_back(readPnm(folder / manifest.images[i].file));
        ASSERT_EQ(ramps.back().channels, 3);
    }
    // Each stop halves the exposure: darker on the ball, stop by stop.
    const procam::SceneFile scene = procam::readSceneFile(installation_.sceneFile);
    const std::vector<std::size_t> ball = ballPixels(scene);
    ASSERT_GT(ball.size(), 1000u);
    for (std::size_t s = 1; s < ramps.size(); ++s) {
        EXPECT_LT(meanOf(ramps[s], ball, 1), meanOf(ramps[s - 1], ball, 1) - 2) << "stop " << s;
    }
    // At the exposure asked for: ramp-e4 is the capture after black, white, the 6 primaries
    // and ramp-e0 (the bracket alternates long and short), at 1/16 of the sensor's exposure.
    const std::size_t first = proto::readScanManifest(out_).images.size();
    const procam::ProcamSimulator simulator(scene.scene, scene.camera);
    procam::SimulatedCamera sensor = scene.camera;
    sensor.monochrome = false;
    sensor.exposure = scene.camera.exposure / 16;
    const procam::CameraFrame truth = simulator.expose(
        simulator.radiance(levelsOf(fields[12], 320, 180)), first + 2 + 6 + 1, sensor);
    EXPECT_TRUE(ramps[4].samples == truth.samples);
}

TEST_F(ScanRadiometryTest, SkipsTheRadiometryOfATenBitGammaCameraInOneLine) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    installation_ = writeScanInstallation(folder_, 10, procam::CameraResponse::kGamma);
    const fs::path board = scanBoard("latency_ms = 0\nphase_period = 64\nphase_steps = 3\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    const std::string reason = installation_.sceneFile.string() +
                               ":camera: a gamma response at 10 bits; a camera response that is "
                               "not linear is measured with an 8-bit bracket (set camera.bits = "
                               "8, or camera.response = \"linear\")";
    EXPECT_EQ(run.err, "vpe-player: scan: no radiometric capture: " + reason + "\n");
    EXPECT_NE(run.out.find("; radiometry: none\n"), std::string::npos) << run.out;
    // The scan is written all the same.
    EXPECT_EQ(proto::readScanManifest(out_).camera.bits, 10);
    EXPECT_FALSE(fs::exists(out_ / proto::kRadiometryFolderName));
    const nlohmann::json report = reportOf(run)["radiometry"];
    EXPECT_EQ(report["captured"], false);
    EXPECT_EQ(report["skipped"], reason);
}

TEST_F(ScanRadiometryTest, BoardTurnsTheRadiometryOff) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board =
        scanBoard("latency_ms = 0\nphase_period = 64\nphase_steps = 3\nradiometry = false\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string(), "--json"});
    ASSERT_EQ(run.status, 0) << run.err;
    EXPECT_TRUE(run.err.empty()) << run.err;
    EXPECT_FALSE(fs::exists(out_ / proto::kRadiometryFolderName));
    EXPECT_EQ(namesIn(out_).size(), proto::readScanManifest(out_).images.size() + 1);
    const nlohmann::json report = reportOf(run)["radiometry"];
    EXPECT_EQ(report["captured"], false);
    EXPECT_EQ(report["skipped"], board.string() + ":scan.radiometry is false");
}

}  // namespace
}  // namespace vpe::firmware
