// SPDX-License-Identifier: MIT
// vpe quilt MODEL.exr --labels labels.png --size WxH|auto [--mesh FILE] [--texel-mm T]
//           [--wrap auto|on|off] --out DIR
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/quilt/texture_quilt.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"
#include "cli/storage_option.h"

namespace vpe::cli {

namespace {

struct QuiltArguments {
    std::string model;
    std::string labels;
    std::string size;
    std::string out;
    std::string mesh;
    double meshScale = 1.0;
    std::optional<double> texelMm;
    std::string wrap = "auto";
    int block = 64;
    int overlap = 12;
    double tolerance = 0.1;
    std::uint64_t seed = 1;
    std::string search = "fft";
    int threads = 0;
    std::string storage;
    bool json = false;
};

// What `vpe quilt` does once its options are parsed.
void runQuilt(const QuiltArguments& args) {
    quilt::QuiltTextureOptions options;
    options.model = args.model;
    options.labels = args.labels;
    options.out = args.out;
    if (args.size != "auto") {
        const SizeArgument size = parseSizeArgument(args.size, "--size");
        options.width = size.width;
        options.height = size.height;
    }
    options.mesh = args.mesh;
    if (!(args.meshScale > 0) || !std::isfinite(args.meshScale)) {
        throw common::InputError("--mesh-scale must be a positive number of metres per unit");
    }
    options.meshMetresPerUnit = args.meshScale;
    options.texelMm = args.texelMm;
    options.wrap = args.wrap == "on"    ? quilt::WrapMode::kOn
                   : args.wrap == "off" ? quilt::WrapMode::kOff
                                        : quilt::WrapMode::kAuto;
    options.settings.block = args.block;
    options.settings.overlap = args.overlap;
    options.settings.tolerance = args.tolerance;
    options.settings.seed = args.seed;
    options.settings.threads = common::resolveThreadCount(args.threads);
    options.storage = parseStorage(args.storage);
    options.settings.search = args.search == "exhaustive"
                                  ? quilt::QuiltSettings::Search::kExhaustive
                                  : quilt::QuiltSettings::Search::kFft;
    if (!(args.tolerance >= 0)) {
        throw common::InputError("--tolerance must be >= 0");
    }
    const quilt::QuiltTextureReport report = quilt::quiltTexture(options);
    const scene::TexelStretch& stretch = report.stretch;
    std::fprintf(stderr, "layout: %dx%d%s for %s%s; ", report.width, report.height,
                 report.autoSize ? " (auto)" : "", report.mesh.c_str(),
                 report.meshWrapsU ? " (u wraps)" : "");
    if (report.texelMm > 0) {
        std::fprintf(stderr, "capture texel %.3g mm, ", report.texelMm);
    }
    std::fprintf(stderr,
                 "texel on the object %.3g x %.3g mm (u x v, geometric means)\n"
                 "stretch (longer / shorter side of a texel on the object): area-weighted "
                 "mean %.2f, median %.2f, p95 %.2f; worst %.2f at uv (%.2f, %.2f)\n",
                 stretch.texelUMm, stretch.texelVMm, stretch.mean, stretch.median, stretch.p95,
                 stretch.worst, static_cast<double>(stretch.worstU),
                 static_cast<double>(stretch.worstV));
    for (const quilt::RegionReport& region : report.regions) {
        std::fprintf(stderr,
                     "region %d: %zu source pixels, %zu candidate blocks of %d (overlap %d, "
                     "%d PCA components of %d channels), %d blocks in %.2f s\n",
                     region.region, region.sourcePixels, region.quilt.candidates,
                     region.quilt.block, region.quilt.overlap, region.quilt.components,
                     report.channels, region.quilt.blocks, region.seconds);
        std::fprintf(stderr,
                     "  u seam (%s): step %.4g, interior neighbours mean %.4g, p95 %.4g, "
                     "max %.4g (%.2fx the mean)\n",
                     report.wrapU ? "tiled" : "not tiled", region.seam.seam,
                     region.seam.interiorMean, region.seam.interiorP95, region.seam.interiorMax,
                     region.seam.ratio());
    }
    std::fprintf(stderr,
                 "quilted %zu regions to %dx%d in %.2f s (load %.2f, quilt %.2f, write %.2f): %s\n",
                 report.regions.size(), report.width, report.height, report.seconds,
                 report.loadSeconds, report.quiltSeconds, report.writeSeconds, args.out.c_str());
    if (args.json) {
        nlohmann::json json = nlohmann::json::parse(quilt::quiltLayoutJson(report));
        json["regions"] = report.regions.size();
        json["channels"] = report.channels;
        json["seconds"] = report.seconds;
        json["load_seconds"] = report.loadSeconds;
        json["quilt_seconds"] = report.quiltSeconds;
        json["write_seconds"] = report.writeSeconds;
        json["out"] = args.out;
        printJson(json.dump());
    }
}

}  // namespace

void addQuiltCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<QuiltArguments>();
    CLI::App* command = app.add_subcommand(
        "quilt", "Image Quilting of a model's coefficient maps, one texture per region");
    command->add_option("MODEL", args->model, "Model file written by vpe fit")->required();
    command->add_option("--labels", args->labels, "Region labels (8-bit PNG, value = region)")
        ->required();
    command
        ->add_option("--size", args->size,
                     "Output size WxH, or auto: a texel as long on the screen object as on the "
                     "captured surface (at most 4096 a side)")
        ->required();
    command->add_option("--mesh", args->mesh,
                        "The screen object the texture is for (OBJ or PLY with UVs): its size and "
                        "seam; default: the built-in vase, as vpe bake's");
    addMeshScaleOption(command, args->meshScale);
    command->add_option("--texel-mm", args->texelMm,
                        "A capture pixel's size on its surface, mm (default: the model's, from the "
                        "capture manifest's texel_mm)");
    command
        ->add_option("--wrap", args->wrap, "Tile in u: auto (when the mesh's u wraps), on or off")
        ->check(CLI::IsMember({"auto", "on", "off"}))
        ->capture_default_str();
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
    addThreadsOption(command, args->threads);
    addStorageOption(command, args->storage, "as MODEL");
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runQuilt(*args); }; });
}

}  // namespace vpe::cli
