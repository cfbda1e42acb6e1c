// SPDX-License-Identifier: MIT
// The texture stage's statistics with quilting on, on a demo-like synthetic capture (camera
// noise): synth → fit → segment → quilt → compose with hidasuki strokes defaulted from the
// source's labels. (a) The coefficient distribution per region of the quilted maps against
// the source region's (vpe quilt-quality's sliced Wasserstein), and of the whole composed
// texture against the whole source; (b) the streaks of the composed weights, and of the
// composed texture segmented again, against the source labels' coverage and widths. The demo's
// old `noise` preset composed the same way fails (b): the thresholds tell streaks from blobs.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/quilt/quilt_quality.h"
#include "vpe/texture/streak_statistics.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::lastJsonLine;
using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

// The label of a two-label map that covers less: the streaks.
int streakRegion(const std::filesystem::path& labels) {
    return texture::measureLabelStreaks(labels, 0).coverage < 0.5 ? 0 : 1;
}

// The valid pixels' coefficient vectors, rows [first, last) of the image.
std::vector<float> validVectors(const model::CoefficientImage& image, int firstRow, int lastRow) {
    std::vector<float> vectors;
    for (int y = firstRow; y < lastRow; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * image.width + x;
            if (image.valid[p] != 0) {
                vectors.insert(vectors.end(), image.at(p), image.at(p) + image.dims);
            }
        }
    }
    return vectors;
}

double slicedDistance(const std::vector<float>& a, const std::vector<float>& b, int dims) {
    return quilt::slicedWasserstein(a.data(), a.size() / static_cast<std::size_t>(dims), b.data(),
                                    b.size() / static_cast<std::size_t>(dims), dims, {});
}

// (a) Per region: the quilt's coefficient distribution against the source region's.
void expectQuiltedRegionsLikeTheSource(const nlohmann::json& report, int streaks) {
    ASSERT_EQ(report["regions"].size(), 2u);
    for (const nlohmann::json& region : report["regions"]) {
        const double ratio = region["sliced_wasserstein"]["ratio"].get<double>();
        std::printf("region %d: sliced Wasserstein %.4f, %.2f × the source's top vs bottom\n",
                    region["region"].get<int>(),
                    region["sliced_wasserstein"]["distance"].get<double>(), ratio);
        // Measured 0.31 (streaks: their top and bottom halves differ more than the quilt
        // differs from both) and 1.62 (ground).
        EXPECT_LT(ratio, region["region"] == streaks ? 0.45 : 2.0) << "region " << region["region"];
    }
}

class TextureStatistics : public ::testing::Test {
protected:
    // synth 96² → fit → segment → quilt 160²: the demo's stages at a third of its sizes
    // (~10 s on 2 busy cores).
    static void SetUpTestSuite() {
        folder_ = new testing::TemporaryFolder;
        const std::string capture = path("capture");
        for (const std::vector<std::string>& arguments :
             {std::vector<std::string>{"synth", "--out", capture, "--size", "96", "--noise",
                                       "camera"},
              {"fit", capture + "/train", "--out", path("model.exr"), "--no-preview"},
              {"segment", path("model.exr"), "--out", path("labels.png"), "--auto", "2"},
              {"quilt", path("model.exr"), "--labels", path("labels.png"), "--size", "160x160",
               "--out", path("quilt")}}) {
            const testing::CommandResult result = runCommand(vpe(arguments));
            ASSERT_EQ(result.exitStatus, 0) << arguments.front() << ": " << result.err;
        }
    }
    static void TearDownTestSuite() {
        delete folder_;
        folder_ = nullptr;
    }
    static std::string path(const std::string& name) { return (*folder_ / name).string(); }

    // Composes the quilt with `spec` into NAME.exr and segments that texture again into
    // NAME-labels.png; returns compose's report.
    static nlohmann::json composeAndSegment(const std::string& name, const std::string& spec) {
        testing::CommandResult result = runCommand(vpe(
            {"compose", path("quilt"), "--out", path(name + ".exr"), "--weights", spec, "--json"}));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        const nlohmann::json report = lastJsonLine(result.out);
        result = runCommand(vpe(
            {"segment", path(name + ".exr"), "--out", path(name + "-labels.png"), "--auto", "2"}));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        return report;
    }

    static testing::TemporaryFolder* folder_;
};

testing::TemporaryFolder* TextureStatistics::folder_ = nullptr;

TEST_F(TextureStatistics, QuiltedAndComposedMapsMeasureLikeTheSource) {
    const testing::CommandResult quality =
        runCommand(vpe({"quilt-quality", path("model.exr"), "--labels", path("labels.png"),
                        "--quilt", path("quilt"), "--json"}));
    ASSERT_EQ(quality.exitStatus, 0) << quality.err;
    expectQuiltedRegionsLikeTheSource(lastJsonLine(quality.out), streakRegion(path("labels.png")));

    const std::filesystem::path labels = path("labels.png");
    const int streaks = streakRegion(labels);
    const texture::StreakStatistics source = texture::measureLabelStreaks(labels, streaks);
    const std::string entry =
        "strokes:from=" + labels.string() + ":region=" + std::to_string(streaks);
    const std::string spec =
        streaks == 0 ? entry + "," + entry + ":invert" : entry + ":invert," + entry;
    const nlohmann::json report = composeAndSegment("strokes", spec);
    ASSERT_EQ(report["strokes"].size(), 1u);
    const nlohmann::json& weights = report["strokes"][0]["composed"];
    const std::filesystem::path again = path("strokes-labels.png");
    const texture::StreakStatistics segmented =
        texture::measureLabelStreaks(again, streakRegion(again));
    std::printf("source:   coverage %.3f, width %.2f [%.2f, %.2f]\n", source.coverage,
                source.widthMedian, source.widthQuartile1, source.widthQuartile3);
    std::printf("weights:  coverage %.3f, width %.2f [%.2f, %.2f]\n",
                weights["coverage"].get<double>(), weights["width_median"].get<double>(),
                weights["width_quartile1"].get<double>(), weights["width_quartile3"].get<double>());
    std::printf("texture:  coverage %.3f, width %.2f [%.2f, %.2f]\n", segmented.coverage,
                segmented.widthMedian, segmented.widthQuartile1, segmented.widthQuartile3);

    // (b) The weights: coverage to within half a stroke's share (6.4% of this map), widths
    // fitted to the source's. Measured: +0.017; median ×1.008, Q1 ×1.000, Q3 ×1.062.
    EXPECT_NEAR(weights["coverage"].get<double>(), source.coverage, 0.025);
    EXPECT_NEAR(weights["width_median"].get<double>() / source.widthMedian, 1, 0.05);
    EXPECT_NEAR(weights["width_quartile1"].get<double>() / source.widthQuartile1, 1, 0.05);
    EXPECT_NEAR(weights["width_quartile3"].get<double>() / source.widthQuartile3, 1, 0.1);
    // The composed texture itself, segmented as the source was: the same figures measured.
    EXPECT_NEAR(segmented.coverage, source.coverage, 0.025);
    EXPECT_NEAR(segmented.widthMedian / source.widthMedian, 1, 0.05);
    EXPECT_NEAR(segmented.widthQuartile1 / source.widthQuartile1, 1, 0.05);
    EXPECT_NEAR(segmented.widthQuartile3 / source.widthQuartile3, 1, 0.1);

    // (a) The whole composed texture against the whole source, relative to the source's top
    // half against its bottom half.
    const model::CoefficientImage model = model::readCoefficientImage(path("model.exr"));
    const model::CoefficientImage composed = model::readCoefficientImage(path("strokes.exr"));
    const double distance = slicedDistance(validVectors(composed, 0, composed.height),
                                           validVectors(model, 0, model.height), model.dims);
    const double self =
        slicedDistance(validVectors(model, 0, model.height / 2),
                       validVectors(model, model.height / 2, model.height), model.dims);
    std::printf("composed vs source: sliced Wasserstein %.4f, %.2f × the source's halves\n",
                distance, distance / self);
    EXPECT_LT(distance / self, 0.5);  // measured 0.40
}

TEST_F(TextureStatistics, TheNoisePresetFailsTheStreakThresholds) {
    const nlohmann::json report = composeAndSegment(
        "noise", "noise:scale=32:sharpness=3:seed=4,noise:scale=32:sharpness=3:seed=4:invert");
    const std::filesystem::path labels = path("labels.png");
    const texture::StreakStatistics source =
        texture::measureLabelStreaks(labels, streakRegion(labels));
    const std::filesystem::path again = path("noise-labels.png");
    const texture::StreakStatistics segmented =
        texture::measureLabelStreaks(again, streakRegion(again));
    std::printf("noise:    coverage %.3f, width %.2f [%.2f, %.2f]\n", segmented.coverage,
                segmented.widthMedian, segmented.widthQuartile1, segmented.widthQuartile3);
    // Measured: coverage 0.463, median width 24.3 (the source's: 0.287, 7.9).
    const bool passes = std::abs(segmented.coverage - source.coverage) <= 0.025 &&
                        std::abs(segmented.widthMedian / source.widthMedian - 1) <= 0.05;
    EXPECT_FALSE(passes);
}

}  // namespace
}  // namespace vpe
