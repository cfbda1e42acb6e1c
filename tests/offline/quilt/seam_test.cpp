// SPDX-License-Identifier: MIT
// The seam at u = 0 | 1, end to end: the synthetic hidasuki material (vpe synth's Fourier
// truth) quilted with and without wrapping, the step from the last column to the first of each
// region's coefficients against the interior neighbour steps; then baked onto the built-in
// vase turned so that the seam faces the projector, and the same on the rendered frame: the
// radiance step between projector pixels on either side of the seam against neighbours that
// do not cross it, near it. Wrapping off must fail the wrapped thresholds (it is asserted to).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/bundle.h"
#include "vpe/quilt/seam_statistics.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/screen_mesh.h"

#include "support/command_runner.h"
#include "support/frame_seam.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

class SeamTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        folder_ = new testing::TemporaryFolder;
        // The truth of a Fourier capture is a model of the hidasuki material itself (no fit); the
        // dome rig keeps the synthesis short.
        const testing::CommandResult synth =
            runCommand(vpe({"synth", "--out", (*folder_ / "capture").string(), "--size", "96",
                            "--rig", "dome", "--reflectance", "fourier"}));
        ASSERT_EQ(synth.exitStatus, 0) << synth.err;
        // The vase turned half a turn about its axis: u = 0 | 1 faces the demo projector.
        scene::ScreenMesh vase = scene::makeProceduralVase();
        for (std::size_t i = 0; i < vase.vertexCount(); ++i) {
            vase.positions[i] = {-vase.positions[i].x, vase.positions[i].y, -vase.positions[i].z};
            vase.normals[i] = {-vase.normals[i].x, vase.normals[i].y, -vase.normals[i].z};
        }
        scene::writeScreenMeshObj(vase, *folder_ / "turned.obj");
    }
    static void TearDownTestSuite() {
        delete folder_;
        folder_ = nullptr;
    }

    // Quilts the truth for the turned vase, wrapping or not; returns the quilt folder.
    static std::string quilt(const std::string& wrap) {
        const std::string out = (*folder_ / ("quilt-" + wrap)).string();
        const std::string capture = (*folder_ / "capture").string();
        const testing::CommandResult result = runCommand(
            vpe({"quilt", capture + "/truth/fourier.exr", "--labels", capture + "/truth/labels.png",
                 "--size", "auto", "--mesh", (*folder_ / "turned.obj").string(), "--wrap", wrap,
                 "--block", "32", "--overlap", "8", "--out", out, "--json"}));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        return out;
    }

    static testing::TemporaryFolder* folder_;
};

testing::TemporaryFolder* SeamTest::folder_ = nullptr;

// Each region's quilted coefficients: with wrapping, the seam's step is an interior one; without,
// a step between unrelated pixels.
TEST_F(SeamTest, QuiltedCoefficientMapsTileInU) {
    double worstOn = 0, bestOff = 1e30;
    for (const std::string wrap : {"on", "off"}) {
        const std::string dir = quilt(wrap);
        for (int region = 0; region < 2; ++region) {
            model::ModelReader reader(dir + "/region" + std::to_string(region) + ".exr");
            const model::ModelInfo info = reader.info();
            EXPECT_EQ(info.tilesU, wrap == "on");
            EXPECT_GT(info.texelMm, 0.0);
            model::ModelRows rows;
            reader.readRows(0, info.height, rows);
            const quilt::SeamStatistics seam = quilt::measureSeam(
                rows.coefficient, info.width, info.height, 3 * rows.coefficients);
            std::cout << "wrap " << wrap << ", region " << region << " (" << info.width << "x"
                      << info.height << "): seam step " << seam.seam << ", interior mean "
                      << seam.interiorMean << ", p95 " << seam.interiorP95 << ", max "
                      << seam.interiorMax << ", ratio " << seam.ratio() << ", rank "
                      << seam.seamRank << "\n";
            if (wrap == "on") {
                worstOn = std::max(worstOn, seam.ratio());
            } else {
                bestOff = std::min(bestOff, seam.ratio());
            }
        }
    }
    // Measured (seam step / interior mean): on 0.94 and 1.06 (interior p95 1.17 and 1.45, max
    // 1.29 and 1.68 of the mean); off 3.08 and 6.45, above every interior column.
    EXPECT_LE(worstOn, 1.15);
    EXPECT_GE(bestOff, 2.8);
}

// Baked and rendered: the bundle says sampling wraps, and across the seam the visitor's
// radiance steps no more than between neighbours beside it.
TEST_F(SeamTest, RenderedFrameHasNoStepAcrossTheSeam) {
    double on = 0, off = 0;
    for (const std::string wrap : {"on", "off"}) {
        const std::string bundle = (*folder_ / ("scene-" + wrap + ".vpeb")).string();
        const testing::CommandResult baked = runCommand(vpe(
            {"bake", "--quilt", quilt(wrap), "--preset", "mix=constant:value=1,constant:value=1",
             "--mesh", (*folder_ / "turned.obj").string(), "--out", bundle}));
        ASSERT_EQ(baked.exitStatus, 0) << baked.err;
        const proto::BundleFile file = proto::BundleFile::open(bundle);
        EXPECT_EQ(file->textureWrapsU(), wrap == "on");
        // In front, above: the seam side is lit.
        const testing::FrameSeamSteps steps =
            testing::measureFrameSeam(file.view(), {0.3, 0.35, 0.6}, 0.03);
        using Steps = testing::FrameSeamSteps;
        std::cout << "wrap " << wrap << ": " << steps.seam.size()
                  << " pixel pairs across the seam, " << steps.interior.size()
                  << " beside it; mean step " << Steps::mean(steps.seam) << " vs "
                  << Steps::mean(steps.interior) << " (p95 "
                  << Steps::quantile(steps.interior, 0.95) << "), ratio " << steps.ratio() << "\n";
        ASSERT_GT(steps.seam.size(), 100u);
        (wrap == "on" ? on : off) = steps.ratio();
    }
    // Measured (mean step across / mean step beside, 542 pairs across): on 1.24 (the interior
    // p95 is 2.9 times its mean), off 9.33.
    EXPECT_LE(on, 1.35);
    EXPECT_GE(off, 8.0);
}

}  // namespace
}  // namespace vpe
