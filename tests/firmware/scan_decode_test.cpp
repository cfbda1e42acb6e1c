// SPDX-License-Identifier: MIT
// What the device writes, the offline side reads: vpe-player --scan's capture of the simulated
// installation decoded by `vpe scan`'s decoder (offline/structured_light), and the projector
// coordinates it finds checked against the simulator's truth. Release build only (it links the
// offline decoder); SKIPs without headless EGL.
#include <cmath>
#include <optional>
#include <string>

#include "vpe/renderer/procam/procam_simulator.h"
#include "vpe/renderer/procam/scene_file.h"
#include "vpe/structured_light/pattern_decoder.h"
#include "vpe/structured_light/scan_capture.h"

#include "scan_fixture.h"

namespace vpe::firmware {
namespace {

using namespace vpe::firmware::testing;

TEST_F(ScanTest, OfflineDecoderReadsThePlayersCapture) {
    if (const std::optional<std::string> why = noHeadlessGles()) {
        GTEST_SKIP() << *why;
    }
    const fs::path board = scanBoard("latency_ms = 0\n");
    const PlayerRun run = play({"--board", board.string(), "--scan", out_.string()});
    ASSERT_EQ(run.status, 0) << run.err;

    const structured_light::ScanCapture capture(out_);
    const structured_light::DecodedScan decoded = structured_light::decodePatterns(capture);
    const renderer::procam::SceneFile scene =
        renderer::procam::readSceneFile(installation_.sceneFile);
    const renderer::procam::ProcamSimulator simulator(scene.scene, scene.camera);
    const renderer::procam::CameraTruth truth = simulator.cameraTruth();

    ASSERT_EQ(decoded.width, 320);
    ASSERT_EQ(decoded.height, 240);
    ASSERT_GT(decoded.lit, 320u * 240u / 4) << "the wall and the ball are lit";
    std::size_t compared = 0, close = 0;
    double worst = 0;
    for (std::size_t p = 0; p < decoded.projectorX.size(); ++p) {
        if (std::isnan(decoded.projectorX[p]) || std::isnan(truth.projectorX[p])) {
            continue;
        }
        const double error = std::max(std::abs(decoded.projectorX[p] - truth.projectorX[p]),
                                      std::abs(decoded.projectorY[p] - truth.projectorY[p]));
        ++compared;
        close += error < 0.5 ? 1 : 0;
        worst = std::max(worst, error);
    }
    const double decodedShare = static_cast<double>(decoded.decoded) / decoded.lit;
    const double closeShare = static_cast<double>(close) / static_cast<double>(compared);
    std::printf(
        "decoded %zu of %zu lit pixels (%.1f%%); %.2f%% of %zu within 0.5 px of the "
        "truth, worst %.2f px\n",
        decoded.decoded, decoded.lit, 100 * decodedShare, 100 * closeShare, compared, worst);
    EXPECT_GT(decodedShare, 0.9);
    EXPECT_GT(closeShare, 0.98);
}

}  // namespace
}  // namespace vpe::firmware
