// SPDX-License-Identifier: MIT
// vpe show-check CAPTURE BUNDLE... [--views N] [--out DIR] [--json]
// What visitors walking around the object see of a show of several projectors, against the
// true material of a synthetic capture (docs/multi-projector.md).
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/transfer/show_fidelity.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct ShowCheckArguments {
    transfer::ShowCheckOptions options;
    std::string capture, out, viewSize = "480x360";
    std::vector<std::string> bundles;
    int threads = 0;
    bool json = false;
};

void runShowCheck(const ShowCheckArguments& args) {
    transfer::ShowCheckOptions options = args.options;
    options.capture = args.capture;
    options.bundles.assign(args.bundles.begin(), args.bundles.end());
    options.out = args.out;
    const SizeArgument size = parseSizeArgument(args.viewSize, "--view-size", 8192);
    options.viewWidth = size.width;
    options.viewHeight = size.height;
    if (!(options.fovDegrees > 0 && options.fovDegrees < 180)) {
        throw common::InputError("--view-fov must be between 0 and 180 degrees");
    }
    if (!(options.elevationDegrees > -90 && options.elevationDegrees < 90)) {
        throw common::InputError("--elevation must be between -90 and 90 degrees");
    }
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    const transfer::ShowCheckReport report = transfer::checkShow(options);
    std::fprintf(stderr, "%8s %8s %10s %10s %8s\n", "azimuth", "PSNR dB", "seam step", "(truth's)",
                 "lit");
    for (const transfer::ShowViewCheck& view : report.views) {
        std::fprintf(
            stderr, "%7.0f° %8.2f %10.3f %10.3f %7.2f%%\n", view.azimuthDegrees, view.psnr,
            view.seamStepRatio, view.truthSeamStepRatio,
            view.seenPixels ? 100.0 * double(view.litPixels) / double(view.seenPixels) : 0.0);
    }
    std::fprintf(stderr,
                 "%zu projectors, %zu views: PSNR mean %.2f dB, worst %.2f; worst seam step "
                 "%.3f× its surroundings; %.2f%% of what visitors see lit; %.1f s\n",
                 options.bundles.size(), report.views.size(), report.meanPsnr, report.worstPsnr,
                 report.worstSeamStepRatio, 100 * report.litShare, report.seconds);
    if (args.json) {
        nlohmann::ordered_json json;
        json["capture"] = args.capture;
        json["bundles"] = args.bundles;
        json["views"] = nlohmann::ordered_json::array();
        for (const transfer::ShowViewCheck& view : report.views) {
            json["views"].push_back({{"azimuth", view.azimuthDegrees},
                                     {"psnr", view.psnr},
                                     {"seam_step_ratio", view.seamStepRatio},
                                     {"picture_seam_step_ratio", view.pictureSeamStepRatio},
                                     {"truth_seam_step_ratio", view.truthSeamStepRatio},
                                     {"boundary_pairs", view.boundaryPairs},
                                     {"seen_pixels", view.seenPixels},
                                     {"lit_pixels", view.litPixels}});
        }
        json["seconds"] = report.seconds;
        json["mean_psnr"] = report.meanPsnr;
        json["worst_psnr"] = report.worstPsnr;
        json["seam_step_ratio"] = report.worstSeamStepRatio;
        json["lit_share"] = report.litShare;
        printJson(json.dump());
    }
}

}  // namespace

void addShowCheckCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ShowCheckArguments>();
    CLI::App* command = app.add_subcommand(
        "show-check",
        "What visitors around the object see of a show of several projectors, against the true "
        "material of a synthetic capture: transfer PSNR, blend seams, lit share");
    command->add_option("CAPTURE", args->capture, "Folder written by vpe synth --out")->required();
    command
        ->add_option("BUNDLE", args->bundles,
                     "The show's bundles (vpe bake with several --projector), or one bundle")
        ->required();
    command->add_option("--views", args->options.views, "Visitors, evenly around the object")
        ->capture_default_str();
    command
        ->add_option("--elevation", args->options.elevationDegrees,
                     "The visitors' eyes above the object's middle (degrees)")
        ->capture_default_str();
    command->add_option("--out", args->out,
                        "Folder for the pictures: viewA-truth.png, viewA-show.png, viewA-reach.png "
                        "(which projectors light each pixel) for azimuth A");
    command->add_option("--view-size", args->viewSize, "View size WxH")->capture_default_str();
    command->add_option("--view-fov", args->options.fovDegrees, "Vertical field of view (degrees)")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runShowCheck(*args); }; });
}

}  // namespace vpe::cli
