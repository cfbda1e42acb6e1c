// SPDX-License-Identifier: MIT
// The control page's install steps on the device side (firmware/scan/install_images.h,
// runCapture): the small grey PNG (a valid file zlib inflates back to the pixels), the camera's
// preview box-averaged to 160 px, the coverage map's three values; and runCapture — the code both
// vpe-player --scan and the page's commands run — in this process on a headless target with the
// simulated camera: a scan and a radiometric capture alone, with their progress, camera view and
// coverage, and a radiometric capture alone written into OUT/radiometry/ beside the scan; and a
// playing vpe-player that takes a controller's command over a broker of the test's own, keeps
// publishing its status while it captures, and draws the very same frame after it as before.
// The runCapture tests SKIP without headless EGL, the player's without mosquitto.
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>
#include <zlib.h>

#include "vpe/firmware/bus/install_message.h"
#include "vpe/firmware/bus/mqtt_connection.h"
#include "vpe/firmware/loop/show_clock.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/scan/install_images.h"
#include "vpe/firmware/scan/scan_run.h"
#include "vpe/firmware/scan/simulated_scan_camera.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/renderer/gles/headless_egl_platform.h"

#include "child_process.h"
#include "mosquitto_broker.h"
#include "scan_installation.h"
#include "test_paths.h"

namespace vpe::firmware {
namespace {

namespace fs = std::filesystem;

std::uint32_t bigEndian(const std::string& bytes, std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at])) << 24 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 3]));
}

CameraImage flat(int width, int height, std::uint16_t value, int maxValue = 255) {
    CameraImage image;
    image.width = width;
    image.height = height;
    image.maxValue = maxValue;
    image.samples.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), value);
    return image;
}

TEST(InstallImagesTest, GreyPngInflatesBackToThePixels) {
    GreyImage image{5, 3, {}};
    for (int i = 0; i < 15; ++i) {
        image.pixels.push_back(static_cast<std::uint8_t>(i * 17));
    }
    const std::string png = encodeGreyPng(image);
    ASSERT_GT(png.size(), 8u + 25u + 12u + 12u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    // IHDR: 5 × 3, 8 bits, grey; its CRC over type and data.
    EXPECT_EQ(bigEndian(png, 8), 13u);
    EXPECT_EQ(png.substr(12, 4), "IHDR");
    EXPECT_EQ(bigEndian(png, 16), 5u);
    EXPECT_EQ(bigEndian(png, 20), 3u);
    EXPECT_EQ(png[24], 8);
    EXPECT_EQ(png[25], 0);
    const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(png.data() + 12), 17);
    EXPECT_EQ(bigEndian(png, 29), static_cast<std::uint32_t>(crc));
    // IDAT inflates to each row after its filter byte 0.
    const std::uint32_t length = bigEndian(png, 33);
    EXPECT_EQ(png.substr(37, 4), "IDAT");
    std::string raw(3 * 6, '\x7f');
    uLongf rawSize = raw.size();
    ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(raw.data()), &rawSize,
                         reinterpret_cast<const Bytef*>(png.data() + 41), length),
              Z_OK);
    ASSERT_EQ(rawSize, 18u);
    for (int y = 0; y < 3; ++y) {
        EXPECT_EQ(raw[static_cast<std::size_t>(y) * 6], '\0');
        for (int x = 0; x < 5; ++x) {
            EXPECT_EQ(static_cast<unsigned char>(raw[static_cast<std::size_t>(y) * 6 + 1 + x]),
                      image.pixels[static_cast<std::size_t>(y) * 5 + x]);
        }
    }
    EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
    EXPECT_THROW(encodeGreyPng(GreyImage{2, 2, {1, 2, 3}}), std::invalid_argument);
}

TEST(InstallImagesTest, PreviewIsBoxAveragedToAtMost160Wide) {
    CameraImage image = flat(330, 20, 0, 1023);
    for (int y = 0; y < 20; ++y) {
        for (int x = 0; x < 330; ++x) {
            image.samples[static_cast<std::size_t>(y) * 330 + x] = x % 3 == 0 ? 1023 : 0;
        }
    }
    const GreyImage preview = cameraPreview(image);
    EXPECT_EQ(preview.width, 110);  // a factor of 3: ceil(330 / 160)
    EXPECT_EQ(preview.height, 7);
    EXPECT_EQ(preview.pixels.front(), 85);  // one sample in three at full scale
    // Colour: Rec. 709 luminance.
    CameraImage green = flat(2, 2, 0);
    green.channels = 3;
    green.samples.assign(12, 0);
    for (std::size_t p = 0; p < 4; ++p) {
        green.samples[3 * p + 1] = 255;
    }
    EXPECT_EQ(cameraPreview(green).pixels, std::vector<std::uint8_t>(4, 182));
}

TEST(InstallImagesTest, CoverageMapSaysDarkLitAndDecodable) {
    // Four pixels: dark; lit with clear Gray pairs; lit with one blurred pair (a stripe's edge:
    // still decodable); lit with two blurred pairs (not).
    const auto row = [](std::vector<std::uint16_t> values) {
        CameraImage image = flat(4, 1, 0);
        image.samples = std::move(values);
        return image;
    };
    CoverageMap map(0.05);
    EXPECT_FALSE(map.known());
    map.setLit(row({12, 200, 200, 200}), row({10, 10, 10, 10}));
    EXPECT_DOUBLE_EQ(map.litFraction(), 0.75);
    EXPECT_EQ(map.image().pixels, (std::vector<std::uint8_t>{0, 96, 96, 96}));
    map.addGrayPair(row({10, 200, 105, 105}), row({12, 10, 105, 105}), 1.0);
    map.addGrayPair(row({10, 10, 10, 100}), row({12, 200, 200, 110}), 1.0);
    EXPECT_TRUE(map.hasGrayPairs());
    EXPECT_DOUBLE_EQ(map.decodableFraction(), 0.5);
    EXPECT_EQ(map.image().pixels, (std::vector<std::uint8_t>{0, 255, 255, 96}));
}

class ScanInstallTest : public ::testing::Test {
protected:
    void SetUp() override {
        try {
            platform_ = renderer::gles::createHeadlessEglPlatform();
        } catch (const renderer::gles::GraphicsError& error) {
            GTEST_SKIP() << "no headless OpenGL ES 3.1: " << error.what();
        }
        folder_ = fs::temp_directory_path() /
                  ("vpe-scan-install-" + std::to_string(::getpid()) + "-" +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(folder_);
        installation_ = testing::writeScanInstallation(folder_);
        board_.source = (folder_ / "board.toml").string();
        board_.display.backend = DisplayBackend::kHeadless;
        ScanConfig scan;
        scan.simulate = installation_.sceneFile;
        scan.latencyMs = 0;
        scan.phasePeriod = 64;
        scan.phaseSteps = 3;
        scan.radiometryLevels = 2;
        board_.scan = scan;
    }
    void TearDown() override { fs::remove_all(folder_); }

    struct Seen {
        std::vector<CaptureProgress> progress;
        int cameraViews = 0;
        std::optional<double> lit, decodable;
        GreyImage coverage;
    };

    ScanReport capture(CaptureKind kind, ScanFolder& folder, Seen& seen) {
        const std::unique_ptr<ScanCamera> camera = openScanCamera(board_);
        const std::array<int, 2> size = scanProjectorSize(*platform_, {}, board_, *camera);
        const auto target = platform_->createRenderTarget(size[0], size[1]);
        int asked = 0;
        CaptureStage stage{*camera, *target, "headless", [&asked] {
                               ++asked;
                               return std::string();
                           }};
        CaptureObserver observer;
        observer.progress = [&seen](const CaptureProgress& p) { seen.progress.push_back(p); };
        observer.cameraView = [&seen](const CameraImage&) { ++seen.cameraViews; };
        observer.coverage = [&seen](const CoverageMap& map) {
            seen.lit = map.litFraction();
            if (map.hasGrayPairs()) {
                seen.decodable = map.decodableFraction();
            }
            seen.coverage = map.image();
        };
        ScanReport report = runCapture(board_, kind, folder, stage, observer);
        EXPECT_GT(asked, static_cast<int>(report.captures));  // after each capture, and waits
        return report;
    }

    std::unique_ptr<renderer::gles::GraphicsPlatform> platform_;
    fs::path folder_;
    testing::ScanInstallation installation_;
    BoardConfig board_;
};

TEST_F(ScanInstallTest, ScanThenRadiometryAloneBesideIt) {
    const fs::path out = folder_ / "scan";
    Seen scan;
    {
        ScanFolder folder(out);
        const ScanReport report = capture(CaptureKind::kScan, folder, scan);
        EXPECT_EQ(report.patterns, 26u);
        EXPECT_TRUE(report.radiometry.captured);
    }
    // 26 patterns, then 8 flat fields (black, white, 2 levels × 3 primaries), one by one.
    ASSERT_EQ(scan.progress.size(), 34u);
    EXPECT_EQ(scan.progress.front().step, "white");
    EXPECT_EQ(scan.progress[25].step, "phase-y-s2");
    EXPECT_EQ(scan.progress.back().done, 34u);
    EXPECT_EQ(scan.progress.back().total, 34u);
    EXPECT_EQ(scan.cameraViews, 1);
    ASSERT_TRUE(scan.lit && scan.decodable);
    EXPECT_GT(*scan.lit, 0.5);
    EXPECT_GT(*scan.decodable, 0.8 * *scan.lit);
    EXPECT_EQ(scan.coverage.width, 160);  // the 320 × 240 camera, halved
    EXPECT_EQ(scan.coverage.height, 120);
    EXPECT_TRUE(fs::exists(out / proto::kScanManifestName));
    EXPECT_TRUE(fs::exists(out / proto::kRadiometryFolderName / proto::kRadiometryManifestName));

    // The radiometric capture alone replaces OUT/radiometry/ and leaves the scan as it was.
    const auto scanWritten = fs::last_write_time(out / proto::kScanManifestName);
    Seen radiometry;
    {
        ScanFolder folder(out / proto::kRadiometryFolderName, proto::kRadiometryManifestName);
        const ScanReport report = capture(CaptureKind::kRadiometry, folder, radiometry);
        EXPECT_EQ(report.patterns, 0u);
        EXPECT_EQ(report.radiometry.fields, 8u);
        EXPECT_EQ(report.summaryLine().rfind("radiometry: 8 flat fields, 8 captures", 0), 0u)
            << report.summaryLine();
    }
    ASSERT_EQ(radiometry.progress.size(), 8u);
    EXPECT_EQ(radiometry.progress.back().step.rfind("radiometry: flat-", 0), 0u);
    EXPECT_EQ(radiometry.cameraViews, 1);
    ASSERT_TRUE(radiometry.lit);
    EXPECT_FALSE(radiometry.decodable);  // no Gray code: lit or dark only
    EXPECT_NEAR(*radiometry.lit, *scan.lit, 0.05);
    EXPECT_EQ(fs::last_write_time(out / proto::kScanManifestName), scanWritten);
    const proto::RadiometryManifest manifest = proto::readRadiometryManifest(
        out / proto::kRadiometryFolderName / proto::kRadiometryManifestName);
    EXPECT_EQ(manifest.images.size(), 8u);
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder_)) {
        ++entries;
    }
    EXPECT_EQ(entries, 3u);  // the installation's two files and the scan: no partial left
}

TEST_F(ScanInstallTest, RadiometryAloneIntoAFreshFolderThenAScanOverIt) {
    const fs::path out = folder_ / "fresh";
    Seen seen;
    {
        ScanFolder folder(out / proto::kRadiometryFolderName, proto::kRadiometryManifestName);
        capture(CaptureKind::kRadiometry, folder, seen);
    }
    EXPECT_TRUE(fs::exists(out / proto::kRadiometryFolderName / proto::kRadiometryManifestName));
    // A folder holding a radiometric capture alone takes a scan.
    ScanFolder folder(out);
    Seen scan;
    capture(CaptureKind::kScan, folder, scan);
    EXPECT_TRUE(fs::exists(out / proto::kScanManifestName));
}

TEST_F(ScanInstallTest, StopsWhenTheCallerSaysSo) {
    const std::unique_ptr<ScanCamera> camera = openScanCamera(board_);
    const std::array<int, 2> size = scanProjectorSize(*platform_, {}, board_, *camera);
    const auto target = platform_->createRenderTarget(size[0], size[1]);
    int asked = 0;
    CaptureStage stage{*camera, *target, "headless",
                       [&asked] { return ++asked > 5 ? std::string("SIGTERM") : std::string(); }};
    const fs::path out = folder_ / "stopped";
    {
        ScanFolder folder(out);
        try {
            runCapture(board_, CaptureKind::kScan, folder, stage);
            ADD_FAILURE() << "not stopped";
        } catch (const ScanError& error) {
            EXPECT_STREQ(error.what(), "scan: stopped by SIGTERM; nothing written");
        }
    }
    EXPECT_FALSE(fs::exists(out));
}

std::string readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST_F(ScanInstallTest, APlayingNodeScansOnCommandAndDrawsTheSameFrameAfter) {
    using namespace bus::testing;
    using namespace std::chrono_literals;
    if (const auto why = MosquittoBroker::unavailable()) {
        GTEST_SKIP() << *why;
    }
    MosquittoBroker broker(folder_ / "broker", {kController, kPlayer}, showAcl());
    broker.start();
    const fs::path bundle = folder_ / "scene.vpeb";
    ASSERT_EQ(std::system((std::string(test_paths::writeTestBundlePath()) + " --out '" +
                           bundle.string() + "' --size 160x90 > /dev/null")
                              .c_str()),
              0);
    // A still light (no drift): every drawn frame is the same picture. Black for 2.5 s before
    // the patterns, so that the capture outlasts a status or two.
    const fs::path board = folder_ / "node-a.toml";
    std::ofstream(board) << "[display]\nbackend = \"headless\"\n[render]\nrate = 30\n"
                            "[idle]\nenabled = false\n[bus]\nhost = \"127.0.0.1\"\nport = "
                         << broker.port() << "\nusername = \"" << kPlayer.name
                         << "\"\npassword = \"" << kPlayer.password
                         << "\"\nshow = \"test\"\nclient_id = \"node-a\"\n[scan]\nsimulate = \""
                         << installation_.sceneFile.string()
                         << "\"\nlatency_ms = 0\nsettle_ms = 2500\nphase_period = 64\n"
                            "phase_steps = 3\nradiometry = false\nout = \"scan\"\n";
    const fs::path frames = folder_ / "frames";
    ChildProcess player({test_paths::playerPath(), "--board", board.string(), "--bundle",
                         bundle.string(), "--out", frames.string(), "--every", "1", "--json"},
                        folder_ / "player.out", folder_ / "player.err");
    const auto waitFor = [](const std::function<bool()>& done, std::chrono::milliseconds limit) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        while (!done() && std::chrono::steady_clock::now() < deadline) {
            std::this_thread::sleep_for(20ms);
        }
        return done();
    };
    const auto err = [&] { return readAll(folder_ / "player.err"); };
    ASSERT_TRUE(waitFor(
        [&] {
            return err().find("bus: connected") != std::string::npos &&
                   fs::exists(frames / "frame_00000.ppm");
        },
        10s))
        << err();

    // The page: a controller that watches node-a's status and install topics.
    std::vector<std::pair<std::string, std::string>> received;
    bus::MqttSettings settings;
    settings.port = broker.port();
    settings.clientId = "vpe-page-test";
    settings.username = kController.name;
    settings.password = kController.password;
    settings.subscriptions = {"vpe/test/status/node-a", "vpe/test/install/node-a/+"};
    bus::MqttConnection::Handlers handlers;
    handlers.message = [&received](std::string_view topic, std::string_view payload, bool) {
        received.emplace_back(std::string(topic), std::string(payload));
    };
    bus::MqttConnection page(settings, std::move(handlers));
    const auto serve = [&](const std::function<bool()>& done, std::chrono::milliseconds limit) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        while (!done() && std::chrono::steady_clock::now() < deadline) {
            page.service(monotonicNowNs());
            std::this_thread::sleep_for(5ms);
        }
        return done();
    };
    ASSERT_TRUE(serve([&] { return page.connected(); }, 5s));
    serve([] { return false; }, 500ms);  // the node's subscriptions in place too
    ASSERT_TRUE(page.publish("vpe/test/command/node-a",
                             bus::encodeInstallCommand({"vpe-page-test", realtimeNowNs() / 1000,
                                                        bus::InstallAction::kScan}),
                             1, false));
    const auto finished = [&] {
        for (const auto& [topic, payload] : received) {
            if (topic == "vpe/test/install/node-a/progress" &&
                payload.find("\"state\":\"running\"") == std::string::npos) {
                return true;
            }
        }
        return false;
    };
    ASSERT_TRUE(serve(finished, 30s)) << err();
    ASSERT_TRUE(serve([&] { return fs::exists(frames / "frame_00001.ppm"); }, 3s)) << err();
    serve([] { return false; }, 300ms);
    EXPECT_EQ(player.stop(), 0);

    // The progress: running from the first step to the last, then done at 26 of 26; statuses
    // went on meanwhile (nothing of the show drawn: fps 0).
    std::vector<nlohmann::json> progress;
    int statusesDuring = 0;
    double lastFpsDuring = -1;  // a whole second of the capture: nothing of the show drawn
    bool capturing = false;
    std::set<std::string> images;
    for (const auto& [topic, payload] : received) {
        if (topic == "vpe/test/install/node-a/progress") {
            progress.push_back(nlohmann::json::parse(payload));
            capturing = progress.back()["state"] == "running";
        } else if (topic == "vpe/test/status/node-a" && capturing) {
            ++statusesDuring;
            lastFpsDuring = nlohmann::json::parse(payload)["fps"].get<double>();
        } else if (topic.rfind("vpe/test/install/node-a/", 0) == 0) {
            images.insert(topic.substr(topic.rfind('/') + 1));
            EXPECT_EQ(payload.substr(1, 3), "PNG");
        }
    }
    ASSERT_GE(progress.size(), 3u);
    EXPECT_EQ(progress.front()["step"], "opening the camera");
    EXPECT_EQ(progress.back()["state"], "done") << progress.back().dump();
    EXPECT_EQ(progress.back()["frames_done"], 26);
    EXPECT_EQ(progress.back()["frames_total"], 26);
    EXPECT_GE(progress.back()["elapsed_s"].get<double>(), 2.5);
    EXPECT_EQ(progress.back()["requested_by"], "vpe-page-test");
    EXPECT_GE(statusesDuring, 2);
    EXPECT_EQ(lastFpsDuring, 0.0);
    EXPECT_EQ(images, (std::set<std::string>{"camera", "coverage"}));
    EXPECT_TRUE(fs::exists(folder_ / "scan" / proto::kScanManifestName));
    // The show resumed as it was: the frame after the capture is the frame before it.
    ASSERT_TRUE(fs::exists(frames / "frame_00001.ppm"));
    EXPECT_EQ(readAll(frames / "frame_00000.ppm"), readAll(frames / "frame_00001.ppm"));
    const std::string out = readAll(folder_ / "player.out");
    const auto report = nlohmann::json::parse(out.substr(out.rfind("\n{") + 1));
    EXPECT_EQ(report["errors"], 0);
    EXPECT_EQ(report["stopped_by"], "SIGTERM");
}

}  // namespace
}  // namespace vpe::firmware
