// SPDX-License-Identifier: MIT
// vpe normals CAPTURE --out normals.png [--truth FILE]
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/parallel_for.h"
#include "vpe/normals/photometric_stereo.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct NormalsArguments {
    std::string capture;
    std::string out;
    std::string truth;
    int threads = 0;
    bool json = false;
};

// What `vpe normals` does once its options are parsed.
void runNormals(const NormalsArguments& args) {
    const capture::Capture capture = capture::openCapture(args.capture);
    normals::PhotometricStereoOptions options;
    options.threads = common::resolveThreadCount(args.threads);
    const normals::NormalMap estimate = normals::estimateNormals(capture, options);
    normals::writeNormalMapPng(args.out, estimate);
    nlohmann::json json;
    std::size_t valid = 0;
    for (std::uint8_t v : estimate.valid) {
        valid += v;
    }
    json["pixels"] = estimate.valid.size();
    json["valid_pixels"] = valid;
    std::optional<std::filesystem::path> truthPath;
    if (!args.truth.empty()) {
        truthPath = args.truth;
    } else if (capture.normalMap) {
        truthPath = capture.normalMap;
    }
    if (truthPath) {
        const normals::NormalMap truth =
            normals::readNormalMap(*truthPath, args.truth.empty() ? capture.normalEncoding
                                                                  : capture::NormalEncoding::kAuto);
        const normals::AngularError error = normals::compareNormalMaps(estimate, truth);
        std::fprintf(stderr, "normals vs %s: mean %.3f°, median %.3f° over %zu pixels\n",
                     truthPath->c_str(), error.meanDegrees, error.medianDegrees, error.pixels);
        json["truth"] = truthPath->string();
        json["mean_error_degrees"] = error.meanDegrees;
        json["median_error_degrees"] = error.medianDegrees;
        json["compared_pixels"] = error.pixels;
    }
    if (args.json) {
        printJson(json.dump());
    }
}

}  // namespace

void addNormalsCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<NormalsArguments>();
    CLI::App* command = app.add_subcommand(
        "normals", "Estimate normals by robust photometric stereo; compare with a reference");
    command->add_option("CAPTURE", args->capture, "Capture (its own normal map is not used)")
        ->required();
    command->add_option("--out", args->out, "Normal map to write, (n + 1)/2 as 8-bit PNG")
        ->required();
    command->add_option("--truth", args->truth,
                        "Reference normal map: report the angular error (default: the "
                        "capture's own normal map, if it has one)");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runNormals(*args); }; });
}

}  // namespace vpe::cli
