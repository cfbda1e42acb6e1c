// SPDX-License-Identifier: MIT
// vpe eval MODEL.exr CAPTURE
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/parallel_for.h"
#include "vpe/eval/model_evaluation.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct EvalArguments {
    std::string model;
    std::string capture;
    std::string predictions;
    int threads = 0;
    int heldOut = 0;
    bool json = false;
};

// What `vpe eval` does once its options are parsed.
void runEval(const EvalArguments& args) {
    eval::EvaluationOptions options;
    options.threads = common::resolveThreadCount(args.threads);
    if (!args.predictions.empty()) {
        options.predictionsDir = args.predictions;
    }
    capture::Capture capture = capture::openCapture(args.capture);
    if (args.heldOut > 0) {
        capture = capture::selectHeldOutLights(capture, args.heldOut, true);
    }
    const eval::EvaluationReport report = eval::evaluateModel(args.model, capture, options);
    if (!args.json) {
        std::printf("%-32s %10s %10s\n", "image", "rms(8bit)", "psnr(dB)");
        for (const eval::ImageScore& image : report.images) {
            std::printf("%-32s %10.3f %10.2f\n", image.name.c_str(), image.rms, image.psnr);
        }
        std::printf("%-32s %10.3f %10.2f\n", "overall", report.rms, report.psnr);
    }
    std::fprintf(stderr,
                 "%zu images, %zu pixels scored (%zu without a valid fit): RMS %.3f "
                 "levels, PSNR %.2f dB (pooled %.2f dB)\n",
                 report.images.size(), report.pixels, report.skippedPixels, report.rms, report.psnr,
                 report.psnrPooled);
    if (args.json) {
        nlohmann::json json;
        json["rms"] = report.rms;
        json["psnr"] = report.psnr;
        json["psnr_pooled"] = report.psnrPooled;
        json["pixels"] = report.pixels;
        json["skipped_pixels"] = report.skippedPixels;
        json["images"] = nlohmann::json::array();
        for (const eval::ImageScore& image : report.images) {
            json["images"].push_back(
                {{"name", image.name}, {"rms", image.rms}, {"psnr", image.psnr}});
        }
        printJson(json.dump());
    }
}

}  // namespace

void addEvalCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<EvalArguments>();
    CLI::App* command = app.add_subcommand(
        "eval", "Predict every image of a capture from a model and report RMS and PSNR");
    command->add_option("MODEL", args->model, "Model file written by vpe fit")->required();
    command->add_option("CAPTURE", args->capture, "Capture to predict (e.g. held-out lights)")
        ->required();
    command->add_option("--predictions", args->predictions,
                        "Folder to write the predicted images to (PNG)");
    addThreadsOption(command, args->threads);
    addHeldOutOption(command, args->heldOut,
                     "Score only every N-th light (positions N-1, 2N-1, ...): those vpe fit "
                     "--held-out N left out");
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runEval(*args); }; });
}

}  // namespace vpe::cli
