// SPDX-License-Identifier: MIT
// vpe weights SPEC --size WxH --out weights.png [--raw] [--json]: a weight spec's maps,
// without region maps, to try patterns before composing or baking them.
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/texture/weight_maps.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/pattern_report.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct WeightsArguments {
    std::string weights;
    std::string size;
    std::string out;
    bool raw = false;
    bool json = false;
};

// What `vpe weights` does once its options are parsed.
void runWeights(const WeightsArguments& args) {
    const std::vector<texture::WeightSource> sources =
        texture::parseWeightSpec(args.weights, "SPEC");
    const SizeArgument size = parseSizeArgument(args.size, "--size");
    texture::WeightMaps weights;
    if (args.raw) {
        weights.width = size.width;
        weights.height = size.height;
        for (const texture::WeightSource& source : sources) {
            weights.alpha.push_back(texture::generateWeight(source, size.width, size.height));
        }
    } else {
        weights = texture::buildWeightMaps(sources, size.width, size.height);
    }
    texture::writeWeightPicture(args.out, weights);
    nlohmann::json patterns;
    reportPatterns(sources, weights, patterns);
    if (args.json) {
        nlohmann::json json;
        json["picture"] = args.out;
        json["width"] = weights.width;
        json["height"] = weights.height;
        json["regions"] = weights.regions();
        json["raw"] = args.raw;
        if (!args.raw) {
            json["zero_weight_pixels"] = weights.zeroSumPixels;
        }
        json.update(patterns);
        printJson(json.dump());
    }
}

}  // namespace

void addWeightsCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<WeightsArguments>();
    CLI::App* command = app.add_subcommand(
        "weights", "Draw a weight spec's normalized maps (as vpe compose --weights-out would)");
    command->add_option("SPEC", args->weights, texture::kWeightSpecSynopsis)->required();
    command->add_option("--size", args->size, "Map size WxH (the texture's)")->required();
    command
        ->add_option("--out", args->out,
                     "Picture to write: a grey tile per region (α from black 0 to white 1), "
                     "then the regions colour-coded")
        ->required();
    command->add_flag("--raw", args->raw,
                      "Draw the raw weights (before normalization; clamped to [0, 1]), so one "
                      "entry shows its own pattern");
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runWeights(*args); }; });
}

}  // namespace vpe::cli
