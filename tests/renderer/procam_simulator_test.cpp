// SPDX-License-Identifier: MIT
// The projector–camera simulator against what physics and its own truth say: Lambertian
// radiance, where each camera pixel sees the projector, the sensor's noise, interreflection,
// the checkerboard, and scene files.
#include "vpe/renderer/procam/procam_simulator.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

#include <gtest/gtest.h>

#include "vpe/renderer/procam/scene_file.h"

#include "test_scenes.h"

namespace vpe::renderer::procam {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A plane 1 m in front of a projector at the origin; the camera 5 cm to its left, both looking
// along +z; no noise, no blur, linear response, no black level, no room light.
ProcamScene planeScene(int projectorWidth = 64, int projectorHeight = 48) {
    const testing::OwnedMesh plane = testing::makePlaneMesh(1.0, 0.5, 4);
    ProcamScene scene;
    scene.object = ScreenObject{plane.positions, plane.normals, plane.uvs, plane.indices, {}};
    scene.projector.camera =
        proto::cameraLookingAt(projectorWidth, projectorHeight, 20, {0, 0, 0}, {0, 0, 1});
    scene.projector.response = proto::ResponseFunction::gamma(1.0);
    scene.projector.blackLevel = {0, 0, 0};
    scene.projector.blurPixels = 0;
    scene.room.interreflection = false;
    scene.albedo.base = {0.8, 0.8, 0.8};
    return scene;
}

SimulatedCamera quietCamera(int width = 80, int height = 60) {
    SimulatedCamera camera;
    camera.camera = proto::cameraLookingAt(width, height, 16, {-0.05, 0, 0}, {0, 0, 1});
    camera.fullWellElectrons = 0;
    camera.readNoiseElectrons = 0;
    camera.bits = 10;
    camera.samples = 2;
    camera.monochrome = false;
    return camera;
}

RgbImage flat(int width, int height, float level) {
    RgbImage image(width, height);
    std::fill(image.values.begin(), image.values.end(), level);
    return image;
}

TEST(ProcamSimulator, FullWhiteGivesTheLambertianRadiance) {
    const SimulatedCamera camera = quietCamera();
    const ProcamSimulator simulator(planeScene(), camera, 2);
    const RgbImage radiance = simulator.radiance(flat(64, 48, 1.0f));
    const CameraTruth truth = simulator.cameraTruth();
    const auto& R = camera.camera.R;
    const auto& T = camera.camera.T;
    // L = ρ/π · P · cos θ / d², the projector at the origin looking along +z onto z = 1.
    int compared = 0;
    for (int y = 20; y < 40; ++y) {
        for (int x = 30; x < 50; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * 80 + x;
            double c[3], room[3];
            for (int i = 0; i < 3; ++i) {
                c[i] = double(truth.pointCamera[3 * p + i]) - T[static_cast<std::size_t>(i)];
            }
            for (int i = 0; i < 3; ++i) {
                room[i] = R[static_cast<std::size_t>(i)] * c[0] +
                          R[static_cast<std::size_t>(3 + i)] * c[1] +
                          R[static_cast<std::size_t>(6 + i)] * c[2];
            }
            EXPECT_NEAR(room[2], 1.0, 1e-6);  // pointCamera holds floats
            const double d2 = room[0] * room[0] + room[1] * room[1] + room[2] * room[2];
            const double expected = 0.8 / kPi * (1.0 / std::sqrt(d2)) / d2;
            EXPECT_NEAR(radiance.pixel(x, y)[0], expected, 1e-4 * expected) << x << "," << y;
            ++compared;
        }
    }
    EXPECT_EQ(compared, 400);
}

TEST(ProcamSimulator, ARampShowsEachPixelItsProjectorCoordinate) {
    ProcamScene scene = planeScene();
    const ProcamSimulator simulator(scene, quietCamera(), 2);
    RgbImage ramp(64, 48);
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 64; ++x) {
            std::fill_n(ramp.pixel(x, y), 3, static_cast<float>(x) / 63.0f);
        }
    }
    const RgbImage lit = simulator.radiance(ramp);
    const RgbImage white = simulator.radiance(flat(64, 48, 1.0f));
    const CameraTruth truth = simulator.cameraTruth();
    int compared = 0;
    for (std::size_t p = 0; p < truth.projectorX.size(); ++p) {
        if (std::isnan(truth.projectorX[p]) || truth.projectorX[p] < 1 ||
            truth.projectorX[p] > 62) {
            continue;
        }
        // Light interpolates linearly between pixel centres: the ramp's share is the coordinate.
        EXPECT_NEAR(double(lit.values[3 * p] / white.values[3 * p]) * 63.0, truth.projectorX[p],
                    1e-3);
        EXPECT_NEAR(truth.projectorX[p], truth.centreX[p], 0.5);
        ++compared;
    }
    EXPECT_GT(compared, 2000);
}

TEST(ProcamSimulator, CrosstalkLeaksEachPrimaryIntoTheOtherChannels) {
    ProcamScene scene = planeScene();
    scene.projector.mixing = {0.9, 0.08, 0.0, 0.06, 0.85, 0.05, 0.0, 0.1, 0.95};
    const ProcamSimulator simulator(scene, quietCamera(), 2);
    RgbImage red(64, 48);
    for (std::size_t i = 0; i < red.values.size(); i += 3) {
        red.values[i] = 1.0f;
    }
    const RgbImage lit = simulator.radiance(red);
    const RgbImage white =
        ProcamSimulator(planeScene(), quietCamera(), 2).radiance(flat(64, 48, 1.0f));
    const std::size_t p = 30 * 80 + 40;
    // Channel k of red light: mixing[3k] of what a pure white primary gives that channel.
    EXPECT_NEAR(lit.values[3 * p] / white.values[3 * p], 0.9, 1e-5);
    EXPECT_NEAR(lit.values[3 * p + 1] / white.values[3 * p + 1], 0.06, 1e-5);
    EXPECT_NEAR(lit.values[3 * p + 2] / white.values[3 * p + 2], 0.0, 1e-6);
}

TEST(ProcamSimulator, TheSensorHasShotAndReadNoise) {
    SimulatedCamera camera = quietCamera();
    camera.fullWellElectrons = 2000;
    camera.readNoiseElectrons = 6;
    camera.exposure = 2.0;
    camera.monochrome = true;
    const ProcamSimulator simulator(planeScene(), camera, 2);
    const RgbImage radiance = simulator.radiance(flat(64, 48, 1.0f));
    const CameraFrame a = simulator.expose(radiance, 7);
    const CameraFrame again = simulator.expose(radiance, 7);
    const CameraFrame b = simulator.expose(radiance, 8);
    EXPECT_EQ(a.samples, again.samples);
    EXPECT_NE(a.samples, b.samples);
    EXPECT_EQ(a.channels, 1);
    EXPECT_EQ(a.maxValue(), 1023);
    // Frame differences remove the scene: var(a − b) = 2σ², σ² = e + r² (electrons).
    double sum = 0, squares = 0, signal = 0;
    int n = 0;
    for (int y = 20; y < 40; ++y) {
        for (int x = 30; x < 50; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * 80 + x;
            const double d = (double(a.samples[p]) - double(b.samples[p])) / 1023;
            sum += d;
            squares += d * d;
            signal += 2.0 * luminance709(radiance.values[3 * p], radiance.values[3 * p + 1],
                                         radiance.values[3 * p + 2]);
            ++n;
        }
    }
    const double variance = squares / n - (sum / n) * (sum / n);
    const double electrons = signal / n * 2000;
    const double expected = 2 * (electrons + 36) / (2000.0 * 2000.0) + 2.0 / (12 * 1023.0 * 1023.0);
    EXPECT_NEAR(variance / expected, 1.0, 0.12);
}

TEST(ProcamSimulator, TheSensorsBlackLevelIsAnOffsetWhateverTheLight) {
    SimulatedCamera camera = quietCamera();
    camera.bits = 10;
    const ProcamSimulator simulator(planeScene(), camera, 2);
    SimulatedCamera pedestal = camera;
    pedestal.blackLevel = 0.004;
    for (const float level : {0.0f, 0.5f}) {
        const RgbImage radiance = simulator.radiance(flat(64, 48, level));
        const CameraFrame without = simulator.expose(radiance, 1);
        const CameraFrame with = simulator.expose(radiance, 1, pedestal);
        for (std::size_t i = 0; i < with.samples.size(); ++i) {
            // 0.004 of 1023 codes, within the code either rounding gives.
            EXPECT_NEAR(double(with.samples[i]) - double(without.samples[i]), 4.092, 1.0) << i;
        }
    }
    camera.blackLevel = 0.5;
    EXPECT_EQ(checkSimulatedCamera(camera), "camera: black level must be in [0, 0.5)");
}

TEST(ProcamSimulator, InterreflectionAddsLightWhereTheSurfaceSeesItself) {
    const testing::OwnedMesh vase = testing::makeVaseMesh(96, 48);
    ProcamScene scene;
    scene.object = ScreenObject{vase.positions, vase.normals, vase.uvs, vase.indices, {}};
    scene.projector.camera = proto::cameraLookingAt(96, 96, 25, {0, 0.075, 0.5}, {0, 0.075, 0});
    scene.projector.blurPixels = 0;
    scene.projector.blackLevel = {0, 0, 0};
    SimulatedCamera camera = quietCamera(96, 96);
    camera.camera = proto::cameraLookingAt(96, 96, 25, {0.1, 0.09, 0.5}, {0, 0.075, 0});
    scene.room.interreflection = false;
    const ProcamSimulator direct(scene, camera, 2);
    scene.room.interreflection = true;
    scene.room.interreflectionGrid = 24;
    const ProcamSimulator bounced(scene, camera, 2);
    const RgbImage white = flat(96, 96, 1.0f);
    const RgbImage a = direct.radiance(white), b = bounced.radiance(white);
    double most = 0;
    const float brightest = *std::max_element(a.values.begin(), a.values.end());
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        EXPECT_GE(b.values[i], a.values[i] * (1 - 1e-6f));
        most = std::max(most, double((b.values[i] - a.values[i]) / brightest));
    }
    // The vase's waist faces its own shoulder and foot: some light more there, a few percent
    // of the brightest direct light (ρ = 0.85, one bounce), not more.
    EXPECT_GT(most, 0.005);
    EXPECT_LT(most, 0.1);
    // Without projector light the bounce has nothing to carry.
    const RgbImage dark = bounced.radiance(flat(96, 96, 0.0f));
    EXPECT_LT(*std::max_element(dark.values.begin(), dark.values.end()), 1e-3f);
}

TEST(ProcamSimulator, TheCheckerboardsFirstSquareIsDark) {
    ProcamScene scene;
    CheckerBoard board;
    board.squareM = 0.02;
    // Facing the devices: board x → +x, y → −y, z → −z; its first inner corner at (−0.08, 0.05,
    // 0.8).
    board.pose.R = {1, 0, 0, 0, -1, 0, 0, 0, -1};
    board.pose.t = {-0.08, 0.05, 0.8};
    scene.board = board;
    scene.projector.camera = proto::cameraLookingAt(64, 48, 30, {0, 0, 0}, {0, 0, 1});
    SimulatedCamera camera = quietCamera(160, 120);
    camera.camera = proto::cameraLookingAt(160, 120, 30, {0, 0, 0}, {0, 0, 1});
    const ProcamSimulator simulator(scene, camera, 2);
    const RgbImage image = simulator.radiance(flat(64, 48, 1.0f));
    for (int j = 0; j < board.cornersY(); ++j) {
        for (int i = 0; i < board.cornersX(); ++i) {
            const auto c = proto::projectToPixel(camera.camera, board.corner(i, j));
            ASSERT_TRUE(c);
            // Diagonal neighbours of a corner: the square up-left of (i, j) is square (i, j).
            const float upLeft = image.pixel(int(c->x - 2.5), int(c->y + 2.5))[0];  // y flips
            const float upRight = image.pixel(int(c->x + 2.5), int(c->y + 2.5))[0];
            EXPECT_EQ((i + j) % 2 == 0, upLeft < upRight) << i << "," << j;
        }
    }
}

TEST(ProcamSimulator, ProjectorTruthSaysWhatTheCameraSees) {
    const testing::OwnedMesh vase = testing::makeVaseMesh(96, 48);
    ProcamScene scene;
    scene.object = ScreenObject{vase.positions, vase.normals, vase.uvs, vase.indices, {}};
    scene.projector.camera = proto::cameraLookingAt(80, 80, 25, {0, 0.075, 0.5}, {0, 0.075, 0});
    scene.room.interreflection = false;
    SimulatedCamera camera = quietCamera(80, 80);
    camera.camera = proto::cameraLookingAt(80, 80, 25, {0.3, 0.075, 0.4}, {0, 0.075, 0});
    const ProcamSimulator simulator(scene, camera, 2);
    const ProjectorTruth truth = simulator.projectorTruth();
    std::size_t lit = 0, seen = 0;
    for (std::size_t p = 0; p < truth.seen.size(); ++p) {
        if (std::isnan(truth.position[3 * p])) {
            EXPECT_EQ(truth.seen[p], 0);
            continue;
        }
        ++lit;
        seen += truth.seen[p];
        EXPECT_GT(truth.position[3 * p + 2], 0.3f);  // in front of the camera
        const double n =
            std::hypot(truth.normal[3 * p], truth.normal[3 * p + 1], truth.normal[3 * p + 2]);
        EXPECT_NEAR(n, 1.0, 1e-5);
    }
    // The camera stands 35° to the side: it sees most, not all, of what the projector lights.
    EXPECT_GT(lit, 1500u);
    EXPECT_GT(seen, lit / 2);
    EXPECT_LT(seen, lit);
}

// The mean and standard deviation of the window's duty over `count` evenly spread starts.
std::pair<double, double> overStarts(const DlpTiming& timing, double duty, int count = 100000) {
    double sum = 0, squares = 0;
    for (int i = 0; i < count; ++i) {
        const double value = dlpWindowDuty(timing, duty, (i + 0.5) / count);
        sum += value;
        squares += value * value;
    }
    const double mean = sum / count;
    return {mean, std::sqrt(std::max(squares / count - mean * mean, 0.0))};
}

TEST(DlpTiming, BinaryLevelsAreExactAndIntermediateOnesSpreadAroundTheirLight) {
    for (const DlpBitOrder order : {DlpBitOrder::kMsbFirst, DlpBitOrder::kLsbFirst}) {
        for (const double frames : {0.3, 0.5, 1.5}) {
            const DlpTiming timing{frames, order};
            for (int i = 0; i < 1000; ++i) {
                const double start = i / 1000.0;
                EXPECT_EQ(dlpWindowDuty(timing, 0.0, start), 0.0);
                EXPECT_EQ(dlpWindowDuty(timing, 1.0, start), 1.0);
            }
            // Over window starts the mean is the level's light, between codes too.
            for (const double duty : {1 / 255.0, 55.6 / 255.0, 0.5, 200.25 / 255.0}) {
                EXPECT_NEAR(overStarts(timing, duty).first, duty, 1e-6)
                    << frames << " frames, duty " << duty;
            }
        }
    }
    // Code 128 is bit-plane 7 alone: on for a = 128/255 of the frame. A window of w = 1/4 frame
    // (shorter than the on and the off spans) sees all on for a − w of the starts, all off for
    // 1 − a − w, and a ramp over 2w: mean a, mean square a − w/3, so σ² = a(1 − a) − w/3.
    const double a = 128 / 255.0, w = 0.25;
    const auto [mean, sigma] = overStarts({w, DlpBitOrder::kMsbFirst}, a);
    EXPECT_NEAR(mean, a, 1e-6);
    EXPECT_NEAR(sigma, std::sqrt(a * (1 - a) - w / 3), 1e-5);  // 0.408
    // A frame and a half sees one whole frame (exact) and half a frame: a third of the spread of
    // the half frame alone.
    const double half = overStarts({0.5, DlpBitOrder::kMsbFirst}, 0.3).second;
    EXPECT_NEAR(overStarts({1.5, DlpBitOrder::kMsbFirst}, 0.3).second, half / 3, 1e-5);
    EXPECT_GT(half, 0.05);
}

TEST(DlpTiming, WholeFramesSeeEveryLevelExactly) {
    for (const DlpBitOrder order : {DlpBitOrder::kMsbFirst, DlpBitOrder::kLsbFirst}) {
        for (const double frames : {1.0, 2.0}) {
            const DlpTiming timing{frames, order};
            for (int code = 0; code <= 255; ++code) {
                for (const double offset : {0.0, 0.4}) {
                    const double duty = std::min((code + offset) / 255.0, 1.0);
                    for (const double start : {0.0, 0.1234, 0.5, 0.999}) {
                        EXPECT_NEAR(dlpWindowDuty(timing, duty, start), duty, 1e-12);
                    }
                }
            }
        }
    }
}

TEST(ProcamSimulator, ADlpWithAShortExposureMisreadsIntermediateLevelsOnly) {
    const SimulatedCamera camera = quietCamera();
    ProcamScene scene = planeScene();
    const ProcamSimulator plain(scene, camera, 2);
    scene.projector.dlp.exposureFrames = 0.3;
    const ProcamSimulator shortExposure(scene, camera, 2);
    scene.projector.dlp.exposureFrames = 2.0;
    const ProcamSimulator wholeFrames(scene, camera, 2);
    const auto centre = [&](const RgbImage& image) {
        return static_cast<double>(image.pixel(40, 30)[1]);
    };
    const RgbImage grey = flat(64, 48, 0.4f), white = flat(64, 48, 1.0f);
    // Off, or whole frames: each frame sees the time-average.
    EXPECT_EQ(plain.radiance(grey, 3).values, plain.radiance(grey).values);
    for (const std::uint64_t frame : {1, 2, 3}) {
        EXPECT_NEAR(centre(wholeFrames.radiance(grey, frame)), centre(plain.radiance(grey)), 1e-6);
        EXPECT_EQ(shortExposure.radiance(white, frame).values, plain.radiance(white).values);
    }
    // A short exposure: a grey differs from frame to frame, the same for the same frame.
    const double first = centre(shortExposure.radiance(grey, 1));
    EXPECT_EQ(centre(shortExposure.radiance(grey, 1)), first);
    double spread = 0;
    for (const std::uint64_t frame : {2, 3, 4, 5}) {
        spread = std::max(spread, std::abs(centre(shortExposure.radiance(grey, frame)) - first));
    }
    EXPECT_GT(spread, 0.05 * centre(plain.radiance(grey)));
}

TEST(ProcamScene, RefusesWhatCannotBeSimulated) {
    ProcamScene scene = planeScene();
    EXPECT_EQ(checkProcamScene(scene), "");
    scene.projector.blackLevel[1] = 1.0;
    EXPECT_EQ(checkProcamScene(scene), "projector: black level must be in [0, 1)");
    scene = planeScene();
    scene.object.reset();
    EXPECT_EQ(checkProcamScene(scene), "the scene has neither an object nor a checkerboard");
    scene = planeScene();
    scene.projector.dlp.exposureFrames = -0.5;
    EXPECT_EQ(checkProcamScene(scene),
              "projector: the DLP exposure must be in [0, 100] frames (0: off)");
    SimulatedCamera camera = quietCamera();
    camera.bits = 12;
    EXPECT_EQ(checkSimulatedCamera(camera), "camera: bits must be 8 or 10");
    EXPECT_THROW(ProcamSimulator(planeScene(), camera, 1), std::invalid_argument);
    EXPECT_THROW(ProcamSimulator(planeScene(), quietCamera(), 1).radiance(flat(10, 10, 1)),
                 std::invalid_argument);
}

TEST(SceneFile, RoundTripsAndNamesBadKeys) {
    const auto folder = std::filesystem::temp_directory_path() / "vpe-scene-file-test";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    {
        std::ofstream obj(folder / "object.obj");
        obj << "v 0 0 1\nv 1 0 1\nv 0 1 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 -1\n"
               "f 1/1/1 2/2/1 3/3/1\n";
    }
    ProcamScene scene = planeScene();
    scene.object->pose.t = {0.01, 0.02, 0.03};
    scene.albedo.stainStrength = 0.2;
    scene.projector.camera.distortion = {-0.03, 0.01, 0.0004, -0.0002, 0};
    SimulatedCamera camera = quietCamera();
    camera.response = CameraResponse::kGamma;
    camera.seed = 42;
    camera.blackLevel = 0.004;
    writeSceneFile(folder / "installation.toml", scene, camera, "object.obj");
    const SceneFile back = readSceneFile(folder / "installation.toml");
    EXPECT_EQ(back.scene.object->positions.size(), 3u);
    EXPECT_EQ(back.scene.object->pose.t, scene.object->pose.t);
    EXPECT_EQ(back.scene.projector.camera.K, scene.projector.camera.K);
    EXPECT_EQ(back.scene.projector.camera.distortion, scene.projector.camera.distortion);
    EXPECT_EQ(back.camera.camera.R, camera.camera.R);
    EXPECT_EQ(back.camera.response, CameraResponse::kGamma);
    EXPECT_EQ(back.camera.seed, 42u);
    EXPECT_DOUBLE_EQ(back.camera.blackLevel, 0.004);
    EXPECT_DOUBLE_EQ(back.scene.albedo.stainStrength, 0.2);
    EXPECT_NEAR(back.scene.projector.response.output(1, 0.5), 0.5, 1e-12);

    // A response that is not a gamma, and crosstalk, read back as written.
    scene.projector.response = proto::ResponseFunction::sampled(
        std::vector<double>{0.0, 0.25, 0.5, 1.0},
        std::array<std::vector<double>, 3>{std::vector<double>{0, 0.1, 0.3, 1},
                                           std::vector<double>{0, 0.05, 0.2, 1},
                                           std::vector<double>{0, 0.08, 0.25, 1}});
    scene.projector.mixing = {0.9, 0.08, 0, 0.06, 0.85, 0.05, 0, 0.1, 0.95};
    writeSceneFile(folder / "curves.toml", scene, camera, "object.obj");
    const SceneFile curves = readSceneFile(folder / "curves.toml");
    EXPECT_FALSE(curves.scene.projector.response.isGamma());
    for (const double level : {0.1, 0.4, 0.8}) {
        EXPECT_NEAR(curves.scene.projector.response.output(1, level),
                    scene.projector.response.output(1, level), 1e-12);
    }
    EXPECT_EQ(curves.scene.projector.mixing, scene.projector.mixing);
    EXPECT_FALSE(curves.scene.projector.dlp.enabled());

    // A DLP's timing, written only when it is on.
    scene.projector.dlp = {0.3, DlpBitOrder::kLsbFirst};
    writeSceneFile(folder / "dlp.toml", scene, camera, "object.obj");
    const SceneFile dlp = readSceneFile(folder / "dlp.toml");
    EXPECT_DOUBLE_EQ(dlp.scene.projector.dlp.exposureFrames, 0.3);
    EXPECT_EQ(dlp.scene.projector.dlp.order, DlpBitOrder::kLsbFirst);

    const auto errorOf = [&](const std::string& text) {
        std::ofstream(folder / "bad.toml") << text;
        try {
            readSceneFile(folder / "bad.toml");
        } catch (const SceneFileError& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    std::ifstream in(folder / "installation.toml");
    std::stringstream good;
    good << in.rdbuf();
    const std::string bad = (folder / "bad.toml").string();
    EXPECT_EQ(errorOf(good.str() + "\n[lights]\nx = 1\n"),
              bad + ":lights: unknown section (object, albedo, board, projector, camera, room)");
    std::string text = good.str();
    text.replace(text.find("bits = 10"), 9, "bits = 12");
    EXPECT_EQ(errorOf(text), bad + ":camera.bits: outside [8, 10]");
    text = good.str();
    text.replace(text.find("[room]"), 6, "[room]\nglow = 1");
    EXPECT_EQ(errorOf(text), bad + ":room.glow: unknown key");
    text = good.str();
    text.replace(text.find("blur_px"), 7, "dlp_exposure_frames = 101\nblur_px");
    EXPECT_EQ(errorOf(text), bad + ":projector.dlp_exposure_frames: outside [0, 100]");
    text = good.str();
    text.replace(text.find("blur_px"), 7, "dlp_bit_order = \"random\"\nblur_px");
    EXPECT_EQ(errorOf(text),
              bad + ":projector.dlp_bit_order: 'random' is not msb_first or lsb_first");
    EXPECT_EQ(errorOf("[camera]\n"), bad + ": projector: missing section");
    std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace vpe::renderer::procam
