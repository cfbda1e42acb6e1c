// SPDX-License-Identifier: MIT
// vpe synth --out DIR
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/common/parallel_for.h"
#include "vpe/synth/capture_synthesizer.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct SynthArguments {
    std::string out;
    int size = 128;
    std::uint64_t seed = 1;
    std::string rig = "paper";
    std::string noise = "none";
    std::string shadows = "on";
    std::string encoding = "linear16";
    std::string reflectance = "microfacet";
    int fourierHarmonics = 4;
    int threads = 0;
    bool json = false;
};

// What `vpe synth` does once its options are parsed.
void runSynth(const SynthArguments& args) {
    synth::SynthOptions options;
    options.out = args.out;
    options.size = args.size;
    options.seed = args.seed;
    options.rig = args.rig;
    options.noise = args.noise == "camera" ? synth::SynthNoise::kCamera : synth::SynthNoise::kNone;
    options.shadows = args.shadows == "on";
    options.encoding = args.encoding == "exr"     ? synth::SynthEncoding::kExr
                       : args.encoding == "srgb8" ? synth::SynthEncoding::kSrgb8
                                                  : synth::SynthEncoding::kLinear16;
    options.reflectance = args.reflectance == "fourier" ? synth::SynthReflectance::kFourier
                                                        : synth::SynthReflectance::kMicrofacet;
    options.fourierHarmonics = args.fourierHarmonics;
    options.threads = common::resolveThreadCount(args.threads);
    const synth::SynthReport report = synth::synthesizeCapture(options);
    std::fprintf(stderr,
                 "wrote %s: %d train + %d held-out images of %dx%d in %.1f s (streaks "
                 "%.0f%% of pixels, relief shadows %.1f%% of lit samples, clipped %.2f%%)\n",
                 args.out.c_str(), report.trainImages, report.testImages, report.size, report.size,
                 report.seconds, 100 * report.streakFraction, 100 * report.shadowedFraction,
                 100 * report.clippedFraction);
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        json["train_images"] = report.trainImages;
        json["test_images"] = report.testImages;
        json["size"] = report.size;
        json["streak_fraction"] = report.streakFraction;
        json["shadowed_fraction"] = report.shadowedFraction;
        json["clipped_fraction"] = report.clippedFraction;
        json["seconds"] = report.seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addSynthCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<SynthArguments>();
    CLI::App* command = app.add_subcommand(
        "synth", "Render the built-in synthetic Bizen capture (train, held-out test, truth)");
    command->add_option("--out", args->out, "Folder to write (train/, test/, truth/)")->required();
    command->add_option("--size", args->size, "Image size in pixels (square)")
        ->capture_default_str();
    command->add_option("--seed", args->seed, "Seed of the procedural pottery")
        ->capture_default_str();
    command->add_option("--rig", args->rig, "paper (330 point lights) or dome (49 directional)")
        ->check(CLI::IsMember({"paper", "dome"}))
        ->capture_default_str();
    command->add_option("--noise", args->noise, "none, or camera (shot + read noise)")
        ->check(CLI::IsMember({"none", "camera"}))
        ->capture_default_str();
    command->add_option("--shadows", args->shadows, "Cast shadows from the relief: on or off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    command
        ->add_option("--encoding", args->encoding,
                     "linear16 (16-bit linear PNG), exr (float) or srgb8 (8-bit sRGB PNG)")
        ->check(CLI::IsMember({"linear16", "exr", "srgb8"}))
        ->capture_default_str();
    command
        ->add_option("--reflectance", args->reflectance,
                     "microfacet (GGX, the default) or fourier (the model itself, for "
                     "exactness checks)")
        ->check(CLI::IsMember({"microfacet", "fourier"}))
        ->capture_default_str();
    command
        ->add_option("--fourier-harmonics", args->fourierHarmonics,
                     "M of the Fourier truth (with --reflectance fourier)")
        ->capture_default_str();
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runSynth(*args); }; });
}

}  // namespace vpe::cli
