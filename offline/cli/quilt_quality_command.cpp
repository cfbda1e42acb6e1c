// SPDX-License-Identifier: MIT
// vpe quilt-quality MODEL.exr --labels labels.png --quilt DIR
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/quilt/quilt_quality.h"
#include "vpe/segment/label_map.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

// NaN (undefined) becomes null.
nlohmann::json number(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json regionJson(const quilt::RegionQuality& q) {
    return {
        {"region", q.region},
        {"output_pixels", q.outputPixels},
        {"positioned_pixels", q.positionedPixels},
        {"source_pixels", q.sourcePixels},
        {"correctness", number(q.correctness)},
        {"correct_pixels", q.correctPixels},
        {"copy_max_difference", number(q.copyMaxDifference)},
        {"sliced_wasserstein",
         {{"distance", number(q.wasserstein)},
          {"self_reference", number(q.wassersteinSelf)},
          {"ratio", number(q.wassersteinRatio)}}},
        {"spectrum",
         {{"distance", number(q.spectrum)},
          {"self_reference", number(q.spectrumSelf)},
          {"ratio", number(q.spectrumRatio)},
          {"window", {q.spectrumWindowWidth, q.spectrumWindowHeight}},
          {"components", q.spectrumComponents},
          {"output_windows", q.spectrumTiles}}},
        {"seams",
         {{"ratio", number(q.seamRatio)},
          {"seam_msd", number(q.seamMsd)},
          {"seam_pairs", q.seamPairs},
          {"interior_msd", number(q.interiorMsd)},
          {"interior_pairs", q.interiorPairs},
          {"interior_reference", q.interiorFromSource ? "source" : "output"}}},
        {"largest_copy",
         {{"pixels", q.largestCopy},
          {"fraction", number(q.largestCopyFraction)},
          {"offset", {q.largestCopyOffsetX, q.largestCopyOffsetY}}}},
    };
}

// A figure, or "n/a" when it is undefined.
// fixed: `digits` decimals; otherwise `digits` significant digits.
std::string figure(double value, bool fixed = false, int digits = 4) {
    if (!std::isfinite(value)) {
        return "n/a";
    }
    char text[32];
    if (fixed) {
        std::snprintf(text, sizeof text, "%.*f", digits, value);
    } else {
        std::snprintf(text, sizeof text, "%.*g", digits, value);
    }
    return text;
}

void printRegion(const quilt::RegionQuality& q) {
    std::printf("region %d: %zu output pixels, %zu with a position; %zu source pixels\n", q.region,
                q.outputPixels, q.positionedPixels, q.sourcePixels);
    std::printf("  region correctness     %s (%zu of %zu copied from the region)\n",
                figure(q.correctness, true, 6).c_str(), q.correctPixels, q.positionedPixels);
    std::printf("  copy max difference    %s\n", figure(q.copyMaxDifference).c_str());
    std::printf("  sliced Wasserstein     %s (source halves %s, ratio %s)\n",
                figure(q.wasserstein).c_str(), figure(q.wassersteinSelf).c_str(),
                figure(q.wassersteinRatio, true, 3).c_str());
    if (q.spectrumTiles > 0) {
        std::printf(
            "  power spectrum         %s (source halves %s, ratio %s; %d × %d windows, %d "
            "components, %d output windows)\n",
            figure(q.spectrum).c_str(), figure(q.spectrumSelf).c_str(),
            figure(q.spectrumRatio, true, 3).c_str(), q.spectrumWindowWidth, q.spectrumWindowHeight,
            q.spectrumComponents, q.spectrumTiles);
    } else {
        std::printf(
            "  power spectrum         n/a (windows of %d × %d, %d components: the region "
            "is too thin or constant)\n",
            q.spectrumWindowWidth, q.spectrumWindowHeight, q.spectrumComponents);
    }
    std::printf(
        "  seams                  ratio %s (seams %s over %zu pairs, interior %s over %zu "
        "%s pairs)\n",
        figure(q.seamRatio, true, 3).c_str(), figure(q.seamMsd).c_str(), q.seamPairs,
        figure(q.interiorMsd).c_str(), q.interiorPairs, q.interiorFromSource ? "source" : "output");
    std::printf("  largest verbatim copy  %zu pixels (%.2f%% of the output, offset %d, %d)\n",
                q.largestCopy, 100.0 * q.largestCopyFraction, q.largestCopyOffsetX,
                q.largestCopyOffsetY);
}

}  // namespace

namespace {

struct QuiltQualityArguments {
    std::string model;
    std::string labels;
    std::string quilt;
    int threads = 0;
    bool json = false;
};

// What `vpe quilt-quality` does once its options are parsed.
void runQuiltQuality(const QuiltQualityArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const model::CoefficientImage source = model::readCoefficientImage(args.model);
    const std::vector<std::uint8_t> labels =
        segment::readLabelImage(args.labels, source.width, source.height).values;
    const std::vector<std::filesystem::path> maps = quilt::listRegionMaps(args.quilt);
    for (int k = 0; k < static_cast<int>(maps.size()); ++k) {
        if (std::find(labels.begin(), labels.end(), k) == labels.end()) {
            throw common::InputError(args.labels, "no pixel of region " + std::to_string(k) + " (" +
                                                      maps[static_cast<std::size_t>(k)].string() +
                                                      " exists)");
        }
    }
    quilt::QualityOptions options;
    options.threads = common::resolveThreadCount(args.threads);
    std::vector<quilt::PositionMap> positions;
    nlohmann::json regions = nlohmann::json::array();
    for (int k = 0; k < static_cast<int>(maps.size()); ++k) {
        const model::CoefficientImage output =
            model::readCoefficientImage(maps[static_cast<std::size_t>(k)]);
        if (output.harmonics != source.harmonics) {
            throw common::InputError(maps[static_cast<std::size_t>(k)],
                                     std::to_string(output.harmonics) + " harmonics, but " +
                                         args.model + " has " + std::to_string(source.harmonics));
        }
        if (k == 0) {
            positions =
                quilt::readPositionMaps(args.quilt, static_cast<int>(maps.size()), output.width,
                                        output.height, source.width, source.height);
        } else if (output.width != positions[0].width || output.height != positions[0].height) {
            throw common::InputError(maps[static_cast<std::size_t>(k)],
                                     "size differs from region0.exr's");
        }
        const quilt::RegionQuality quality = quilt::measureRegionQuality(
            source, labels, k, output, positions[static_cast<std::size_t>(k)], options);
        if (!args.json) {
            printRegion(quality);
        }
        regions.push_back(regionJson(quality));
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "measured %zu region maps in %.2f s\n", maps.size(), seconds);
    if (args.json) {
        nlohmann::json json;
        json["model"] = args.model;
        json["labels"] = args.labels;
        json["quilt"] = args.quilt;
        json["regions"] = regions;
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addQuiltQualityCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<QuiltQualityArguments>();
    CLI::App* command = app.add_subcommand(
        "quilt-quality",
        "Measure a quilting result: region correctness, distribution and spectrum match, seams, "
        "verbatim copies (docs/quilt-quality.md)");
    command->add_option("MODEL", args->model, "The model that was quilted (.exr)")->required();
    command->add_option("--labels", args->labels, "Its region labels (8-bit, value = region)")
        ->required();
    command
        ->add_option("--quilt", args->quilt,
                     "Folder vpe quilt wrote (region<k>.exr, positions.exr)")
        ->required();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runQuiltQuality(*args); }; });
}

}  // namespace vpe::cli
