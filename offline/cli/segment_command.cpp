// SPDX-License-Identifier: MIT
// vpe segment MODEL.exr --out labels.png (--seeds x,y[;x,y...] | --auto K|auto) [--truth FILE]
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/image/image_file.h"
#include "vpe/segment/label_comparison.h"
#include "vpe/segment/segmentation.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

// "x,y;x,y;..." → seeds; anything else is named back to the user.
std::vector<segment::PixelSeed> parseSeeds(const std::string& text) {
    std::vector<segment::PixelSeed> seeds;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find(';', start), text.size());
        const std::string item = text.substr(start, end - start);
        const std::size_t comma = item.find(',');
        segment::PixelSeed seed;
        std::size_t usedX = 0, usedY = 0;
        bool ok = comma != std::string::npos && comma > 0 && comma + 1 < item.size();
        try {
            if (ok) {
                const std::string xs = item.substr(0, comma), ys = item.substr(comma + 1);
                seed.x = std::stoi(xs, &usedX);
                seed.y = std::stoi(ys, &usedY);
                ok = usedX == xs.size() && usedY == ys.size();
            }
        } catch (const std::exception&) {
            ok = false;
        }
        if (!ok) {
            throw common::InputError("--seeds: '" + item +
                                     "' is not a pixel x,y (expected x,y[;x,y...])");
        }
        seeds.push_back(seed);
        start = end + 1;
    }
    return seeds;
}

int parseClusters(const std::string& text) {
    if (text == "auto") {
        return 0;
    }
    std::size_t used = 0;
    int k = -1;
    try {
        k = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || k < 1 || k > segment::LabelMap::kMaxLabels) {
        throw common::InputError("--auto: expected 'auto' or a number of labels K from 1 to " +
                                 std::to_string(segment::LabelMap::kMaxLabels) + ", got '" + text +
                                 "'");
    }
    return k;
}

}  // namespace

namespace {

struct SegmentArguments {
    std::string model;
    std::string out;
    std::string seeds;
    std::string autoClusters;
    std::string truth;
    std::string space = "appearance";
    std::string average;
    long minIsland = -1;
    std::uint64_t seed = 1;
    int threads = 0;
    bool json = false;
};

// What `vpe segment` does once its options are parsed.
void runSegment(const SegmentArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    if (args.seeds.empty() == args.autoClusters.empty()) {
        throw common::InputError("segment: give either --seeds x,y[;x,y...] or --auto K|auto");
    }
    segment::SegmentOptions options;
    if (!args.seeds.empty()) {
        options.seeds = parseSeeds(args.seeds);
        options.seedSpace =
            args.space == "colour" ? segment::SeedSpace::kColour : segment::SeedSpace::kAppearance;
    } else {
        options.clusters = parseClusters(args.autoClusters);
    }
    options.minIsland = args.minIsland;
    options.seed = args.seed;
    options.threads = common::resolveThreadCount(args.threads);
    // The truth is read first, so a bad one stops the command before any work.
    std::optional<segment::LabelMap> truth;
    if (!args.truth.empty()) {
        truth = segment::readLabelImage(args.truth);
    }
    segment::AppearanceOptions appearanceOptions;
    appearanceOptions.threads = options.threads;
    const segment::Appearance appearance =
        segment::computeAppearance(args.model, appearanceOptions);
    if (truth && (truth->width != appearance.width || truth->height != appearance.height)) {
        throw common::InputError(args.truth, "is " + std::to_string(truth->width) + "x" +
                                                 std::to_string(truth->height) + ", the model " +
                                                 std::to_string(appearance.width) + "x" +
                                                 std::to_string(appearance.height));
    }
    const segment::SegmentResult result = segment::segmentAppearance(appearance, options);
    const std::filesystem::path overlay = segment::overlayPathFor(args.out);
    segment::writeLabelImage(args.out, result.map);
    segment::writeLabelOverlay(overlay, result.map, appearance);
    if (!args.average.empty()) {
        image::writeImage8(args.average, appearance.width, appearance.height, 3,
                           segment::averagePicture(appearance));
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    nlohmann::json json;
    json["model"] = args.model;
    json["out"] = args.out;
    json["overlay"] = overlay.string();
    json["mode"] = options.seeds.empty() ? "auto" : "seeds";
    if (!options.seeds.empty()) {
        json["space"] = args.space;
    }
    json["labels"] = result.map.labels;
    json["label_pixels"] = segment::labelAreas(result.map);
    json["pixels"] = result.map.values.size();
    json["valid_pixels"] = appearance.validPixels;
    json["min_island"] = result.minIsland;
    json["islands_merged"] = result.islandsMerged;
    json["explained_variance"] = appearance.explainedVariance;
    if (options.seeds.empty()) {
        json["clusters"] = result.clusters;
        json["seed"] = args.seed;
        if (!result.candidates.empty()) {
            nlohmann::json silhouettes;
            for (std::size_t i = 0; i < result.candidates.size(); ++i) {
                silhouettes[std::to_string(result.candidates[i])] = result.silhouettes[i];
            }
            json["silhouettes"] = silhouettes;
        }
    }
    std::string chosen;
    if (!result.candidates.empty()) {
        chosen = " (K chosen by silhouette)";
    }
    std::fprintf(stderr, "%s: %d labels%s, %zu islands merged (< %zu px), %.2f s\n",
                 args.out.c_str(), result.map.labels, chosen.c_str(), result.islandsMerged,
                 result.minIsland, seconds);
    if (truth) {
        const segment::LabelComparison comparison = segment::compareLabels(result.map, *truth);
        json["truth"] = args.truth;
        json["truth_labels"] = comparison.truthLabels;
        json["matched_labels"] = comparison.matchedLabels;
        json["iou"] = comparison.iou;
        json["mean_iou"] = comparison.meanIou;
        json["compared_pixels"] = comparison.comparedPixels;
        std::fprintf(stderr, "vs %s: mean IoU %.4f over %zu labels (", args.truth.c_str(),
                     comparison.meanIou, comparison.truthLabels.size());
        for (std::size_t i = 0; i < comparison.iou.size() && i < 16; ++i) {
            std::fprintf(stderr, "%s%d: %.3f", i ? ", " : "", comparison.truthLabels[i],
                         comparison.iou[i]);
        }
        std::fprintf(stderr, "%s)\n", comparison.iou.size() > 16 ? ", ..." : "");
    }
    json["seconds"] = seconds;
    if (args.json) {
        printJson(json.dump());
    }
}

}  // namespace

void addSegmentCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<SegmentArguments>();
    CLI::App* command = app.add_subcommand(
        "segment", "Split a model into reflectance regions: label image and overlay");
    command->add_option("MODEL", args->model, "Model file (.exr) from vpe fit")->required();
    command
        ->add_option("--out", args->out,
                     "Label image to write (8-bit PNG, value = label; 255 = no valid fit); "
                     "the overlay goes next to it as NAME-overlay.png")
        ->required();
    CLI::Option* seedsOption = command->add_option(
        "--seeds", args->seeds,
        "Seeded: one pixel x,y per region, ';'-separated; each pixel joins the seed of the "
        "nearest average colour");
    CLI::Option* autoOption = command->add_option(
        "--auto", args->autoClusters,
        "Automatic: K regions by k-means on colour and coefficients, or 'auto' to choose K in "
        "2..8 by the silhouette");
    seedsOption->excludes(autoOption);
    command
        ->add_option("--space", args->space,
                     "What seeds compare: 'appearance' (colour and coefficients) or 'colour' "
                     "(the paper's: average colour only)")
        ->check(CLI::IsMember({"appearance", "colour"}))
        ->capture_default_str();
    command->add_option("--truth", args->truth,
                        "Reference label image: report the IoU per label and the mean");
    command->add_option("--average", args->average,
                        "Also write the average image (what seeds are picked on)");
    command->add_option("--min-island", args->minIsland,
                        "Regions smaller than this many pixels join their surroundings "
                        "(default: 0.2% of the valid pixels)");
    command->add_option("--seed", args->seed, "Random seed of the clustering")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runSegment(*args); }; });
}

}  // namespace vpe::cli
