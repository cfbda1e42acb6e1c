// SPDX-License-Identifier: MIT
// vpe sweep TRAIN TEST --out DIR
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/parallel_for.h"
#include "vpe/eval/fourier_sweep.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct SweepArguments {
    std::string train;
    std::string test;
    std::string out;
    std::string normals;
    int maxHarmonics = 15;
    std::vector<double> lambdas{0.0, 0.5, 3.14, 10.0, 50.0};
    int threads = 0;
    bool json = false;
};

// What `vpe sweep` does once its options are parsed.
void runSweep(const SweepArguments& args) {
    eval::SweepOptions options;
    options.maxHarmonics = args.maxHarmonics;
    options.lambdas = args.lambdas;
    options.threads = common::resolveThreadCount(args.threads);
    if (!args.normals.empty()) {
        options.normals = args.normals;
    }
    const capture::Capture train = capture::openCapture(args.train);
    const capture::Capture test = capture::openCapture(args.test);
    const eval::SweepResult result = eval::runSweep(train, test, options);
    const std::filesystem::path out(args.out);
    eval::writeSweepCsv(out / "sweep.csv", result);
    eval::writeSweepPlot(out / "sweep.svg", result);
    std::printf("%8s", "M");
    for (double lambda : result.lambdas) {
        std::printf("  λ=%-8g", lambda);
    }
    std::printf("   (RMS, 8-bit levels)\n");
    for (std::size_t m = 0; m < result.harmonics.size(); ++m) {
        std::printf("%8d", result.harmonics[m]);
        for (std::size_t l = 0; l < result.lambdas.size(); ++l) {
            std::printf("  %-10.3f", result.rms[l][m]);
        }
        std::printf("\n");
    }
    std::fprintf(stderr, "sweep of %zu pixels, %d train / %d test images in %.1f s: %s\n",
                 result.pixels, result.trainImages, result.testImages, result.seconds,
                 (out / "sweep.svg").c_str());
    if (args.json) {
        nlohmann::json json;
        json["harmonics"] = result.harmonics;
        json["lambdas"] = result.lambdas;
        json["rms"] = result.rms;
        json["psnr"] = result.psnr;
        json["valid_fraction"] = result.validFraction;
        json["pixels"] = result.pixels;
        json["seconds"] = result.seconds;
        json["csv"] = (out / "sweep.csv").string();
        json["plot"] = (out / "sweep.svg").string();
        printJson(json.dump());
    }
}

}  // namespace

void addSweepCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<SweepArguments>();
    CLI::App* command = app.add_subcommand(
        "sweep", "The paper's Fig. 6: held-out RMS for M = 1..15 and several λ (CSV + SVG)");
    command->add_option("TRAIN", args->train, "Capture to fit")->required();
    command->add_option("TEST", args->test, "Capture to score on (held-out lights)")->required();
    command->add_option("--out", args->out, "Folder for sweep.csv and sweep.svg")->required();
    command->add_option("--normals", args->normals, "Normal map for TRAIN");
    command->add_option("--max-harmonics", args->maxHarmonics, "Largest M")->capture_default_str();
    command->add_option("--lambdas", args->lambdas, "λ values")->delimiter(',');
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runSweep(*args); }; });
}

}  // namespace vpe::cli
