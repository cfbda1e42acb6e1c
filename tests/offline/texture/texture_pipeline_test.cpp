// SPDX-License-Identifier: MIT
// The texture stage end to end, as the demo runs it: a built-in synthetic capture, fitted,
// segmented (automatically and from seeds) against its true materials, quilted per region,
// measured, and composed; and the bad-input contract of `vpe segment` and `vpe quilt`.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/model/fourier_model_file.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/segment/label_map.h"
#include "vpe/text/line_reader.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/fitted_capture.h"
#include "support/label_seeds.h"
#include "support/test_data.h"
#include "support/vpe_command_names.h"

namespace vpe {
namespace {

using namespace testing::vpe_command_names;  // NOLINT: support/vpe_command_names.h

std::string fileBytes(const std::filesystem::path& file) {
    return text::readTextFile(file, "position map");
}

// One fitted synthetic capture shared by the tests here (rendering and fitting it is the
// slow part: ~3 s).
class TexturePipeline : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        folder_ = new testing::TemporaryFolder;
        if (testing::suiteRunsMoreThanItsRefusals()) {
            ASSERT_NO_FATAL_FAILURE(testing::synthesizeAndFit(*folder_ / "capture", model(), 96));
        }
    }
    static void TearDownTestSuite() {
        delete folder_;
        folder_ = nullptr;
    }
    static std::string path(const std::string& name) { return (*folder_ / name).string(); }
    static std::string model() { return path("model.exr"); }
    static std::string truth() { return path("capture/truth/labels.png"); }
    // The refusals' capture and model: a small fit that every refusal shares.
    static std::string small(const std::string& name) {
        return (testing::smallFittedCapture() / name).string();
    }

    static testing::TemporaryFolder* folder_;
};

testing::TemporaryFolder* TexturePipeline::folder_ = nullptr;

TEST_F(TexturePipeline, AutomaticSegmentationFindsTheTwoMaterials) {
    const testing::CommandResult result =
        runCommand(vpe({"segment", model(), "--out", path("auto.png"), "--auto", "auto", "--truth",
                        truth(), "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJsonLine(result.out);
    EXPECT_EQ(report["clusters"], 2);  // chosen by the silhouette among 2..8
    EXPECT_GE(report["mean_iou"].get<double>(), 0.95);
    EXPECT_TRUE(std::filesystem::exists(path("auto-overlay.png")));
}

TEST_F(TexturePipeline, SeededSegmentationFindsTheTwoMaterials) {
    const std::string seeds =
        testing::seedsArgument(testing::innermostPixels(segment::readLabelImage(truth())));
    for (const char* space : {"appearance", "colour"}) {
        const testing::CommandResult result =
            runCommand(vpe({"segment", model(), "--out", path("seeded.png"), "--seeds", seeds,
                            "--space", space, "--truth", truth(), "--json"}));
        ASSERT_EQ(result.exitStatus, 0) << result.err;
        const nlohmann::json report = lastJsonLine(result.out);
        EXPECT_EQ(report["labels"], 2);
        EXPECT_GE(report["mean_iou"].get<double>(), 0.95) << space;
    }
}

TEST_F(TexturePipeline, QuiltMeasureAndCompose) {
    ASSERT_EQ(runCommand(vpe({"segment", model(), "--out", path("labels.png"), "--auto", "2"}))
                  .exitStatus,
              0);
    const std::string quilt = path("quilt");
    testing::CommandResult result =
        runCommand(vpe({"quilt", model(), "--labels", path("labels.png"), "--size", "96x80",
                        "--block", "16", "--overlap", "4", "--out", quilt, "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    nlohmann::json report = lastJsonLine(result.out);
    EXPECT_EQ(report["regions"], 2);
    EXPECT_EQ(report["width"], 96);
    EXPECT_EQ(report["height"], 80);
    EXPECT_GT(report["seconds"].get<double>(), 0.0);
    for (int region = 0; region < 2; ++region) {
        EXPECT_TRUE(std::filesystem::exists(quilt::regionMapPath(quilt, region)));
        EXPECT_TRUE(std::filesystem::exists(quilt::positionsPath(quilt, region)));
    }
    // The relief travels with its texels: every quilted pixel's detail normal is its source's.
    {
        model::ModelReader source(model());
        ASSERT_TRUE(source.info().detailNormals);
        model::ModelRows sourceRows;
        source.readRows(0, source.info().height, sourceRows);
        const std::vector<quilt::PositionMap> positions =
            quilt::readPositionMaps(quilt, 2, 96, 80, source.info().width, source.info().height);
        for (int region = 0; region < 2; ++region) {
            model::ModelReader quilted(quilt::regionMapPath(quilt, region));
            ASSERT_TRUE(quilted.info().detailNormals);
            model::ModelRows rows;
            quilted.readRows(0, 80, rows);
            std::size_t differing = 0, tilted = 0;
            for (int y = 0; y < 80; ++y) {
                for (int x = 0; x < 96; ++x) {
                    const std::size_t p = positions[static_cast<std::size_t>(region)].pixel(x, y);
                    const std::size_t from =
                        sourceRows.pixel(positions[static_cast<std::size_t>(region)].sourceY[p],
                                         positions[static_cast<std::size_t>(region)].sourceX[p]);
                    for (int a = 0; a < 3; ++a) {
                        differing += rows.detail[p * 3 + a] != sourceRows.detail[from * 3 + a];
                    }
                    tilted += rows.detail[p * 3 + 2] < 0.999f ? 1 : 0;
                }
            }
            EXPECT_EQ(differing, 0u) << region;
            EXPECT_GT(tilted, 96u * 80u / 4) << "the synthetic relief tilts most normals";
        }
    }

    result = runCommand(vpe(
        {"quilt-quality", model(), "--labels", path("labels.png"), "--quilt", quilt, "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    report = lastJsonLine(result.out);
    for (const nlohmann::json& region : report["regions"]) {
        EXPECT_DOUBLE_EQ(region["correctness"].get<double>(), 1.0);  // every source in region
        EXPECT_DOUBLE_EQ(region["copy_max_difference"].get<double>(), 0.0);
        EXPECT_LT(region["largest_copy"]["fraction"].get<double>(), 0.5);
    }

    result = runCommand(vpe({"compose", quilt, "--out", path("composed.exr"), "--weights",
                             "stripes:period=32,stripes:period=32:invert", "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    // 2.5 periods of stripes over 80 rows: near, not exactly, half each.
    EXPECT_NEAR(lastJsonLine(result.out)["weights"][0]["mean"].get<double>(), 0.5, 0.1);
    // The composite carries the blended relief, unit length.
    {
        model::ModelReader composed(path("composed.exr"));
        ASSERT_TRUE(composed.info().detailNormals);
        model::ModelRows rows;
        composed.readRows(0, 80, rows);
        for (std::size_t p = 0; p < rows.valid.size(); ++p) {
            const double length =
                std::hypot(rows.detail[p * 3], rows.detail[p * 3 + 1], rows.detail[p * 3 + 2]);
            // Stored as half floats (the fit's default storage, which compose keeps): each
            // component within 2⁻¹¹ relative, so the length within 2⁻¹¹ of 1 (measured 1.5e-4).
            ASSERT_NEAR(length, 1.0, std::ldexp(1.0, -11)) << p;
        }
    }
    result = runCommand(vpe(
        {"relight", path("composed.exr"), "--out", path("composed.png"), "--light", "0.3,0.4,1"}));
    EXPECT_EQ(result.exitStatus, 0) << result.err;
}

// --size auto: the capture's texel (its manifest's texel_mm, through vpe fit) as long on the
// screen object; the built-in vase's u wraps, so the maps tile; a flat mesh gets exactly its
// size and no wrapping; sizes beyond what a bundle holds are refused by name.
TEST_F(TexturePipeline, QuiltSizesItselfForTheScreenObjectAndTilesAroundIt) {
    ASSERT_EQ(
        runCommand(vpe({"segment", model(), "--out", path("sized.png"), "--auto", "2"})).exitStatus,
        0);
    auto quilt = [&](const std::string& out, std::vector<std::string> extra) {
        std::vector<std::string> arguments{"quilt",   model(),   "--labels",  path("sized.png"),
                                           "--block", "16",      "--overlap", "4",
                                           "--out",   path(out), "--json"};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        return runCommand(vpe(arguments));
    };
    testing::CommandResult result = quilt("auto", {"--size", "auto"});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    nlohmann::json report = lastJsonLine(result.out);
    EXPECT_EQ(report["size_auto"], true);
    EXPECT_EQ(report["mesh_wraps_u"], true);
    EXPECT_EQ(report["wrap_u"], true);
    // 96 pixels across 108.4 mm of the synthetic pot's front.
    EXPECT_NEAR(report["texel_mm"].get<double>(), 108.38 / 96, 0.01);
    EXPECT_NEAR(report["stretch"]["texel_u_mm"].get<double>(), 108.38 / 96, 0.01);
    EXPECT_NEAR(report["stretch"]["texel_v_mm"].get<double>(), 108.38 / 96, 0.01);
    EXPECT_GT(report["width"].get<int>(), report["height"].get<int>());
    EXPECT_LT(report["stretch"]["median"].get<double>(), 1.3);
    for (const nlohmann::json& seam : report["seams"]) {
        EXPECT_LT(seam["ratio"].get<double>(), 1.6) << seam;
    }
    EXPECT_NE(result.err.find("stretch"), std::string::npos) << result.err;

    {  // A 0.1 × 0.05 m card, uv over [0, 1]²: 200 × 100 texels of 0.5 mm, nothing wraps.
        std::ofstream obj(path("card.obj"));
        obj << "v 0 0 0\nv 0.1 0 0\nv 0.1 0.05 0\nv 0 0.05 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
               "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
    }
    result = quilt("card", {"--size", "auto", "--mesh", path("card.obj"), "--texel-mm", "0.5"});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    report = lastJsonLine(result.out);
    EXPECT_EQ(report["width"], 200);
    EXPECT_EQ(report["height"], 100);
    EXPECT_EQ(report["wrap_u"], false);
    EXPECT_NEAR(report["stretch"]["worst"].get<double>(), 1.0, 1e-6);

    result = quilt("off", {"--size", "64x48", "--wrap", "off"});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    EXPECT_EQ(lastJsonLine(result.out)["wrap_u"], false);

    expectInputError(quilt("big", {"--size", "auto", "--texel-mm", "0.05"}),
                     {"--size auto", "4096"});
    expectInputError(quilt("narrow", {"--size", "12x40", "--wrap", "on"}), {"wraps in u", "12"});
    expectInputError(quilt("neg", {"--size", "auto", "--texel-mm", "-1"}), {"--texel-mm"});
    EXPECT_FALSE(std::filesystem::exists(path("big")));
}

// The fit wrote half floats (its default); quilt and compose keep their input's storage
// unless --storage says otherwise.
TEST_F(TexturePipeline, QuiltAndComposeWriteTheirInputsStorageUnlessTold) {
    ASSERT_EQ(model::ModelReader(model()).info().storage, model::ModelStorage::kHalf);
    ASSERT_EQ(
        runCommand(vpe({"segment", model(), "--out", path("st.png"), "--auto", "2"})).exitStatus,
        0);
    for (const char* storage : {"", "float"}) {
        const std::string quilt = path(std::string("st-quilt-") + storage);
        std::vector<std::string> arguments{"quilt",     model(), "--labels", path("st.png"),
                                           "--size",    "48x48", "--block",  "12",
                                           "--overlap", "3",     "--out",    quilt};
        if (*storage != '\0') {
            arguments.insert(arguments.end(), {"--storage", storage});
        }
        testing::CommandResult result = runCommand(vpe(arguments));
        ASSERT_EQ(result.exitStatus, 0) << result.err;
        const model::ModelStorage expected =
            *storage ? model::ModelStorage::kFloat : model::ModelStorage::kHalf;
        EXPECT_EQ(model::ModelReader(quilt::regionMapPath(quilt, 1)).info().storage, expected)
            << storage;
        result = runCommand(
            vpe({"compose", quilt, "--out", quilt + ".exr", "--weights", "constant,constant"}));
        ASSERT_EQ(result.exitStatus, 0) << result.err;
        EXPECT_EQ(model::ModelReader(quilt + ".exr").info().storage, expected) << storage;
    }
    const testing::CommandResult result =
        runCommand(vpe({"compose", path("st-quilt-"), "--out", path("st.exr"), "--weights",
                        "constant,constant", "--storage", "float"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    EXPECT_EQ(model::ModelReader(path("st.exr")).info().storage, model::ModelStorage::kFloat);
}

TEST_F(TexturePipeline, QuiltIsDeterministicWhateverTheThreads) {
    ASSERT_EQ(
        runCommand(vpe({"segment", model(), "--out", path("det.png"), "--auto", "2"})).exitStatus,
        0);
    for (const char* threads : {"1", "2"}) {
        const testing::CommandResult result =
            runCommand(vpe({"quilt", model(), "--labels", path("det.png"), "--size", "64x64",
                            "--block", "12", "--overlap", "3", "--seed", "9", "--threads", threads,
                            "--out", path(std::string("det") + threads)}));
        ASSERT_EQ(result.exitStatus, 0) << result.err;
    }
    for (int region = 0; region < 2; ++region) {
        EXPECT_EQ(fileBytes(quilt::positionsPath(path("det1"), region)),
                  fileBytes(quilt::positionsPath(path("det2"), region)))
            << "region " << region << ": position maps differ between 1 and 2 threads";
    }
}

TEST_F(TexturePipeline, SegmentRefusesBadInputNamingIt) {
    const std::string out = path("bad/labels.png");
    expectInputError(runCommand(vpe({"segment", small("model.exr"), "--out", out})),
                     {"--seeds", "--auto"});
    expectInputError(
        runCommand(vpe({"segment", small("model.exr"), "--out", out, "--seeds", "1,2;x"})),
        {"'x'"});
    expectInputError(
        runCommand(vpe({"segment", small("model.exr"), "--out", out, "--seeds", "5,5;500,3"})),
        {"(500, 3)", "outside"});
    expectInputError(runCommand(vpe({"segment", small("model.exr"), "--out", out, "--auto", "0"})),
                     {"--auto", "'0'"});
    expectInputError(runCommand(vpe({"segment", path("missing.exr"), "--out", out, "--auto", "2"})),
                     {"missing.exr"});
    expectInputError(runCommand(vpe({"segment", small("model.exr"), "--out", out, "--auto", "2",
                                     "--truth", small("capture/truth/normals.png")})),
                     {"normals.png"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(TexturePipeline, QuiltRefusesBadInputNamingIt) {
    ASSERT_EQ(
        runCommand(vpe({"segment", small("model.exr"), "--out", path("q.png"), "--auto", "2"}))
            .exitStatus,
        0);
    const std::string out = path("badquilt");
    auto quilt = [&](std::vector<std::string> extra) {
        std::vector<std::string> arguments{
            "quilt", small("model.exr"), "--labels", path("q.png"), "--out", out};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        return runCommand(vpe(arguments));
    };
    expectInputError(quilt({"--size", "96"}), {"--size", "96"});
    expectInputError(quilt({"--size", "0x10"}), {"--size"});
    expectInputError(quilt({"--size", "64x64", "--overlap", "40", "--block", "16"}), {"overlap"});
    expectInputError(
        runCommand(vpe({"quilt", small("model.exr"), "--labels", small("capture/truth/normals.png"),
                        "--size", "64x64", "--out", out})),
        {"normals.png"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace vpe
