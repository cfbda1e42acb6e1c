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
#include "vpe/transfer/visitors_together.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct ShowCheckArguments {
    transfer::ShowCheckOptions options;
    std::string together;  // viewer models, comma-separated: visitors standing at once
    std::string capture, out, viewSize = "480x360";
    std::vector<std::string> bundles;
    int threads = 0;
    bool json = false;
};

// Several visitors at once under one light, the frames drawn once per viewer model.
void runTogether(const ShowCheckArguments& args, const transfer::ShowCheckOptions& options) {
    transfer::TogetherOptions together;
    together.show = options;
    std::vector<transfer::ViewerModel> models;
    std::size_t from = 0;
    while (from <= args.together.size()) {
        const std::size_t comma = std::min(args.together.find(',', from), args.together.size());
        models.push_back(
            transfer::parseViewerModel(args.together.substr(from, comma - from), "--together"));
        from = comma + 1;
    }
    nlohmann::ordered_json json;
    json["capture"] = args.capture;
    json["bundles"] = args.bundles;
    json["models"] = nlohmann::ordered_json::object();
    for (const transfer::ViewerModel model : models) {
        const transfer::TogetherReport report = transfer::checkVisitorsTogether(together, model);
        const std::string name = transfer::viewerModelName(model);
        std::fprintf(stderr, "%s: %6s %8s %8s %10s %6s\n", name.c_str(), "where", "azimuth",
                     "PSNR dB", "highlights", "lit");
        nlohmann::ordered_json visitors = nlohmann::ordered_json::array();
        nlohmann::ordered_json above;
        for (const transfer::VisitorCheck& v : report.visitors) {
            const double lit = v.seenPixels ? double(v.litPixels) / double(v.seenPixels) : 0.0;
            std::fprintf(stderr, "%*s  %6s %7.0f° %8.2f %9.1f%% %5.1f%%\n",
                         static_cast<int>(name.size()), "", v.where.c_str(), v.azimuthDegrees,
                         v.psnr, 100 * v.highlightShare, 100 * lit);
            nlohmann::ordered_json one = {{"where", v.where},
                                          {"azimuth", v.azimuthDegrees},
                                          {"elevation", v.elevationDegrees},
                                          {"psnr", v.psnr},
                                          {"highlight_share", v.highlightShare},
                                          {"lit_share", lit}};
            if (v.where == "above") {
                above = one;
            }
            visitors.push_back(std::move(one));
        }
        std::fprintf(stderr,
                     "%s: standing visitors' PSNR worst %.2f dB, mean %.2f; highlights seen "
                     "%.1f%% (worst %.1f%%); %.1f s\n",
                     name.c_str(), report.worstPsnr, report.meanPsnr,
                     100 * report.meanHighlightShare, 100 * report.worstHighlightShare,
                     report.seconds);
        json["models"][name] = {{"worst_psnr", report.worstPsnr},
                                {"mean_psnr", report.meanPsnr},
                                {"highlight_share", report.meanHighlightShare},
                                {"worst_highlight_share", report.worstHighlightShare},
                                {"above", above},
                                {"visitors", visitors},
                                {"seconds", report.seconds}};
    }
    if (args.json) {
        printJson(json.dump());
    }
}

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
    if (!args.together.empty()) {
        runTogether(args, options);
        return;
    }
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
    command->add_option(
        "--together", args->together,
        "Visitors standing at once under one light (8 at eye height, 2 children, 1 above), the "
        "frames drawn once for each viewer model given: bundle, projector-side, zone, tracked "
        "(comma-separated); --out gets MODEL-WHERE-AZIMUTH.png, truth | show | difference ×4");
    command->add_option("--view-size", args->viewSize, "View size WxH")->capture_default_str();
    command->add_option("--view-fov", args->options.fovDegrees, "Vertical field of view (degrees)")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runShowCheck(*args); }; });
}

}  // namespace vpe::cli
