// SPDX-License-Identifier: MIT
// vpe quilt MODEL.exr --labels labels.png --size WxH --out DIR
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/size_argument.h"
#include "common/input_error.h"
#include "common/parallel_for.h"
#include "quilt/texture_quilt.h"

namespace vpe::cli {

void addQuiltCommand(CLI::App& app, Action& action) {
    struct Arguments {
        std::string model;
        std::string labels;
        std::string size;
        std::string out;
        int block = 64;
        int overlap = 12;
        double tolerance = 0.1;
        std::uint64_t seed = 1;
        std::string search = "fft";
        int threads = 0;
        bool json = false;
    };
    auto args = std::make_shared<Arguments>();
    CLI::App* command = app.add_subcommand(
        "quilt", "Image Quilting of a model's coefficient maps, one texture per region");
    command->add_option("MODEL", args->model, "Model file written by vpe fit")->required();
    command->add_option("--labels", args->labels, "Region labels (8-bit PNG, value = region)")
        ->required();
    command->add_option("--size", args->size, "Output size WxH")->required();
    command->add_option("--out", args->out, "Folder for region<k>.exr and positions<k>.exr")
        ->required();
    command->add_option("--block", args->block, "Block size in pixels")->capture_default_str();
    command->add_option("--overlap", args->overlap, "Overlap in pixels")->capture_default_str();
    command
        ->add_option("--tolerance", args->tolerance,
                     "ε: pick at random within (1 + ε) of the best overlap error")
        ->capture_default_str();
    command->add_option("--seed", args->seed, "Random seed")->capture_default_str();
    command
        ->add_option("--search", args->search,
                     "fft (PCA + FFT overlap search) or exhaustive (all channels, slow)")
        ->check(CLI::IsMember({"fft", "exhaustive"}))
        ->capture_default_str();
    command->add_option("--threads", args->threads, "Worker threads (0: all cores)");
    command->add_flag("--json", args->json, "End stdout with a JSON report");
    command->callback([args, &action] {
        action = [args] {
            quilt::QuiltTextureOptions options;
            options.model = args->model;
            options.labels = args->labels;
            options.out = args->out;
            const SizeArgument size = parseSizeArgument(args->size, "--size");
            options.width = size.width;
            options.height = size.height;
            options.settings.block = args->block;
            options.settings.overlap = args->overlap;
            options.settings.tolerance = args->tolerance;
            options.settings.seed = args->seed;
            options.settings.threads = resolveThreadCount(args->threads);
            options.settings.search = args->search == "exhaustive"
                                          ? quilt::QuiltSettings::Search::kExhaustive
                                          : quilt::QuiltSettings::Search::kFft;
            if (!(args->tolerance >= 0)) {
                throw InputError("--tolerance must be >= 0");
            }
            const quilt::QuiltTextureReport report = quilt::quiltTexture(options);
            for (const quilt::RegionReport& region : report.regions) {
                std::fprintf(
                    stderr,
                    "region %d: %zu source pixels, %zu candidate blocks of %d (overlap %d, "
                    "%d PCA components of %d channels), %d blocks in %.2f s\n",
                    region.region, region.sourcePixels, region.quilt.candidates, region.quilt.block,
                    region.quilt.overlap, region.quilt.components, report.channels,
                    region.quilt.blocks, region.seconds);
            }
            std::fprintf(
                stderr,
                "quilted %zu regions to %dx%d in %.2f s (load %.2f, quilt %.2f, write %.2f): %s\n",
                report.regions.size(), size.width, size.height, report.seconds, report.loadSeconds,
                report.quiltSeconds, report.writeSeconds, args->out.c_str());
            if (args->json) {
                nlohmann::json json;
                json["regions"] = report.regions.size();
                json["width"] = size.width;
                json["height"] = size.height;
                json["channels"] = report.channels;
                json["seconds"] = report.seconds;
                json["load_seconds"] = report.loadSeconds;
                json["quilt_seconds"] = report.quiltSeconds;
                json["write_seconds"] = report.writeSeconds;
                json["out"] = args->out;
                printJson(json.dump());
            }
        };
    });
}

}  // namespace vpe::cli
