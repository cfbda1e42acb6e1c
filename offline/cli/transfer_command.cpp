// SPDX-License-Identifier: MIT
// vpe transfer CAPTURE BUNDLE [--out DIR] [--views NAME,...] [--json]
// Transfer fidelity: the true material of a synthetic capture against what the pipeline
// renders from its fitted model on the screen object (docs/transfer-fidelity.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/transfer/transfer_fidelity.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct TransferArguments {
    std::string capture, bundle, out, views, viewSize = "480x360";
    double fov = 20.0;
    int threads = 0;
    bool json = false;
    bool trueRelief = false;
};

// What `vpe transfer` does once its options are parsed.
void runTransfer(const TransferArguments& args) {
    transfer::TransferOptions options;
    options.capture = args.capture;
    options.bundle = args.bundle;
    options.out = args.out;
    const SizeArgument size = parseSizeArgument(args.viewSize, "--view-size", 8192);
    options.viewWidth = size.width;
    options.viewHeight = size.height;
    if (!(args.fov > 0 && args.fov < 180)) {
        throw common::InputError("--view-fov must be between 0 and 180 degrees");
    }
    options.fovDegrees = args.fov;
    std::stringstream views(args.views);
    for (std::string name; std::getline(views, name, ',');) {
        if (!name.empty()) {
            options.views.push_back(name);
        }
    }
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    options.trueRelief = args.trueRelief;
    const transfer::TransferReport report = transfer::measureTransferFidelity(options);
    std::fprintf(stderr, "%-13s %8s %7s %12s %6s\n", "view", "PSNR dB", "SSIM", "object dB", "lit");
    for (const transfer::ViewFidelity& view : report.views) {
        std::fprintf(stderr, "%-13s %8.2f %7.4f %12.2f %5.0f%%\n", view.name.c_str(), view.psnr,
                     view.ssim, view.psnrObject, 100.0 * view.litShare);
    }
    std::fprintf(stderr,
                 "mean PSNR %.2f dB (worst %.2f, %s), mean SSIM %.4f; relief off the "
                 "truth's by %.2f° on average%s\n",
                 report.psnr, report.worstPsnr, report.worstView.c_str(), report.ssim,
                 report.reliefErrorDegrees, report.relief ? "" : " (the bundle carries no relief)");
    if (args.json) {
        // Ordered, the summary last: scripts read the last "psnr" and "ssim".
        nlohmann::ordered_json json;
        json["capture"] = args.capture;
        json["bundle"] = args.bundle;
        json["relief"] = report.relief;
        json["true_relief"] = args.trueRelief;
        json["relief_error_degrees"] = report.reliefErrorDegrees;
        json["texture_width"] = report.textureWidth;
        json["texture_height"] = report.textureHeight;
        json["views"] = nlohmann::ordered_json::array();
        for (const transfer::ViewFidelity& view : report.views) {
            json["views"].push_back(nlohmann::ordered_json{{"name", view.name},
                                                           {"psnr", view.psnr},
                                                           {"ssim", view.ssim},
                                                           {"psnr_object", view.psnrObject},
                                                           {"lit_share", view.litShare},
                                                           {"exposure", view.exposure},
                                                           {"object_pixels", view.objectPixels}});
        }
        json["worst_psnr"] = report.worstPsnr;
        json["worst_view"] = report.worstView;
        json["seconds"] = report.seconds;
        json["ssim"] = report.ssim;
        json["psnr"] = report.psnr;
        printJson(json.dump());
    }
}

}  // namespace

void addTransferCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<TransferArguments>();
    CLI::App* command = app.add_subcommand(
        "transfer",
        "Transfer fidelity: a synthetic capture's true material against the pipeline's "
        "rendering of its fitted model on the bundle's object, under new lights and views");
    command->add_option("CAPTURE", args->capture, "Folder written by vpe synth --out")->required();
    command
        ->add_option("BUNDLE", args->bundle,
                     "Bundle baked from a fit of that capture: vpe bake --texture MODEL.exr")
        ->required();
    command->add_option("--out", args->out,
                        "Folder for the pictures: VIEW-truth.png, VIEW-pipeline.png, "
                        "VIEW-difference.png (|truth − pipeline| × 4)");
    command->add_option("--views", args->views,
                        "Comma-separated view names (default: all; docs/transfer-fidelity.md)");
    command->add_option("--view-size", args->viewSize, "View size WxH")->capture_default_str();
    command->add_option("--view-fov", args->fov, "Vertical field of view (degrees)")
        ->capture_default_str();
    command->add_flag("--true-relief", args->trueRelief,
                      "Diagnostic: render the pipeline with the truth's relief instead of the "
                      "bundle's (what the relief's estimate costs)");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runTransfer(*args); }; });
}

}  // namespace vpe::cli
