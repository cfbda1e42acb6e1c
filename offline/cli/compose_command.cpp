// SPDX-License-Identifier: MIT
// vpe compose DIR --out composed.exr --weights SPEC [--weights-out weights.png]
#include <chrono>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/texture/region_compose.h"
#include "vpe/texture/weight_maps.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/pattern_report.h"
#include "cli/storage_option.h"

namespace vpe::cli {

namespace {

struct ComposeArguments {
    std::string dir;
    std::string out;
    std::string weights;
    std::string weightsOut;
    std::string storage;
    bool json = false;
};

// What `vpe compose` does once its options are parsed.
void runCompose(const ComposeArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    // The spec first: its mistakes are cheaper to report than a folder's.
    const std::vector<texture::WeightSource> sources = texture::parseWeightSpec(args.weights);
    const std::vector<std::filesystem::path> maps = quilt::listRegionMaps(args.dir);
    if (sources.size() != maps.size()) {
        throw common::InputError("--weights has " + std::to_string(sources.size()) +
                                 (sources.size() == 1 ? " entry" : " entries") + " but " +
                                 args.dir + " holds " + std::to_string(maps.size()) +
                                 " region maps (region0.exr .. " + maps.back().filename().string() +
                                 "): one entry per region");
    }
    const model::ModelInfo info = texture::checkRegionMaps(maps);
    const texture::WeightMaps weights = texture::buildWeightMaps(sources, info.width, info.height);
    const texture::ComposeReport report =
        texture::composeRegionMaps(maps, weights, args.out, parseStorage(args.storage));
    if (!args.weightsOut.empty()) {
        texture::writeWeightPicture(args.weightsOut, weights);
    }
    nlohmann::json patterns;
    reportPatterns(sources, weights, patterns);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "composed %d region maps of %d × %d (M = %d) into %s in %.2f s; mean "
                 "weights",
                 report.regions, report.width, report.height, report.harmonics, args.out.c_str(),
                 seconds);
    for (double mean : report.meanWeight) {
        std::fprintf(stderr, " %.3f", mean);
    }
    std::fprintf(stderr, "\n");
    if (weights.zeroSumPixels > 0) {
        std::fprintf(stderr, "%zu pixels had all weights 0 and got equal weights\n",
                     weights.zeroSumPixels);
    }
    if (report.invalidPixels > 0) {
        std::fprintf(stderr,
                     "%zu pixels are invalid: a region weighted there has no valid "
                     "coefficients\n",
                     report.invalidPixels);
    }
    if (args.json) {
        nlohmann::json json;
        json["model"] = args.out;
        json["width"] = report.width;
        json["height"] = report.height;
        json["harmonics"] = report.harmonics;
        json["regions"] = report.regions;
        json["region_maps"] = nlohmann::json::array();
        for (const auto& map : maps) {
            json["region_maps"].push_back(map.string());
        }
        json["weights"] = nlohmann::json::array();
        for (std::size_t k = 0; k < sources.size(); ++k) {
            json["weights"].push_back(
                {{"entry", sources[k].entry}, {"mean", report.meanWeight[k]}});
        }
        json["zero_weight_pixels"] = weights.zeroSumPixels;
        json.update(patterns);
        json["invalid_pixels"] = report.invalidPixels;
        if (!args.weightsOut.empty()) {
            json["weights_picture"] = args.weightsOut;
        }
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addComposeCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ComposeArguments>();
    CLI::App* command = app.add_subcommand(
        "compose", "Blend the region maps of vpe quilt with weight maps into one model (eq. 20)");
    command->add_option("DIR", args->dir, "Folder with region0.exr, region1.exr, ... (vpe quilt)")
        ->required();
    command->add_option("--out", args->out, "Model file to write (.exr)")->required();
    command->add_option("--weights", args->weights, texture::kWeightSpecSynopsis)->required();
    command->add_option("--weights-out", args->weightsOut,
                        "Picture of the normalized weights: a grey tile per region, then the "
                        "regions colour-coded");
    addStorageOption(command, args->storage, "as region0.exr");
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runCompose(*args); }; });
}

}  // namespace vpe::cli
