// SPDX-License-Identifier: MIT
// vpe export-relight MODEL.exr CAPTURE --out DIR [--resolution R] [--planes K] [--quality Q]
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/parallel_for.h"
#include "vpe/relight_web/model_relight_export.h"

#include "cli/commands.h"
#include "cli/common_options.h"

namespace vpe::cli {

namespace {

struct ExportRelightArguments {
    std::string model;
    std::string capture;
    std::string out;
    int resolution = relight_web::RelightWebOptions{}.resolution;
    int planes = relight_web::RelightWebOptions{}.planes;
    int quality = relight_web::RelightWebOptions{}.quality;
    std::string grid = "least-squares";
    int heldOut = 0;
    int threads = 0;
    bool json = false;
};

// What `vpe export-relight` does once its options are parsed.
void runExportRelight(const ExportRelightArguments& args) {
    relight_web::RelightWebOptions options;
    options.resolution = args.resolution;
    options.planes = args.planes;
    options.quality = args.quality;
    options.threads = common::resolveThreadCount(args.threads);
    options.grid = args.grid == "nodes" ? relight_web::GridValues::kNodes
                                        : relight_web::GridValues::kLeastSquares;
    const capture::Capture capture = capture::openCapture(args.capture);
    const capture::Capture check =
        args.heldOut > 0 ? selectHeldOutLights(capture, args.heldOut, true) : capture::Capture{};
    const relight_web::RelightModelExport result =
        exportModelToRelight(args.model, capture, args.out, options, check);
    const relight_web::RelightRoundTrip& trip = result.roundTrip;
    std::fprintf(
        stderr, "%s: %dx%d, bilinear %dx%d grid, %d planes (%.4f of the variance), %.1f KiB\n",
        args.out.c_str(), result.summary.width, result.summary.height, result.summary.resolution,
        result.summary.resolution, result.summary.planes, result.summary.retainedVariance,
        static_cast<double>(result.summary.bytes) / 1024.0);
    std::fprintf(stderr,
                 "round trip against the model under %d capture lights: as OpenLIME shows it "
                 "PSNR %.2f dB (worst %.2f dB); decoded, before OpenLIME's 8-bit linear buffer, "
                 "%.2f dB (worst %.2f dB); the model's own prediction through that buffer "
                 "%.2f dB (worst %.2f dB)\n",
                 trip.lights, trip.viewer.mean, trip.viewer.worst, trip.decoded.mean,
                 trip.decoded.worst, trip.displayOnly.mean, trip.displayOnly.worst);
    std::fprintf(
        stderr,
        "decoded values below 0 at the %d grid lights: %zu, in %zu pixels (lowest decoded "
        "value %.1f/255); %zu pixels solved under the floor, %zu again in %d rounds against "
        "the planes' rounding, mean lifted by up to %.0f/255\n",
        result.summary.resolution * result.summary.resolution, trip.negative.values,
        trip.negative.pixels, 255.0 * trip.negative.lowest, result.summary.flooredPixels,
        result.summary.repairedPixels, result.summary.repairRounds,
        255.0 * result.summary.meanLift);
    if (args.json) {
        const auto psnrs = [](const relight_web::LightPsnrs& p) {
            return nlohmann::json{
                {"psnr", p.mean}, {"worst_psnr", p.worst}, {"per_light", p.perLight}};
        };
        nlohmann::json json;
        json["out"] = args.out;
        json["width"] = result.summary.width;
        json["height"] = result.summary.height;
        json["resolution"] = result.summary.resolution;
        json["planes"] = result.summary.planes;
        json["retained_variance"] = result.summary.retainedVariance;
        json["bytes"] = result.summary.bytes;
        json["floor"] = {{"floored_pixels", result.summary.flooredPixels},
                         {"repaired_pixels", result.summary.repairedPixels},
                         {"repair_rounds", result.summary.repairRounds},
                         {"mean_lift", result.summary.meanLift},
                         {"lowest_at_nodes", result.summary.lowestAtNodes}};
        // psnr, worst_psnr and per_light: what a viewer sees in OpenLIME.
        json["round_trip"] = psnrs(trip.viewer);
        json["round_trip"]["lights"] = trip.lights;
        json["round_trip"]["pixels"] = trip.pixels;
        json["round_trip"]["shown_as"] = "openlime";
        json["round_trip"]["decoded"] = psnrs(trip.decoded);
        json["round_trip"]["display_only"] = psnrs(trip.displayOnly);
        json["round_trip"]["below_zero_at_grid"] = {{"values", trip.negative.values},
                                                    {"pixels", trip.negative.pixels},
                                                    {"nodes", trip.negative.nodes},
                                                    {"lowest", trip.negative.lowest}};
        printJson(json.dump());
    }
}

}  // namespace

void addExportRelightCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ExportRelightArguments>();
    CLI::App* command = app.add_subcommand(
        "export-relight",
        "Export a model as a Relight web RTI (info.json + plane_N.jpg, bilinear light grid, "
        "PCA planes) for OpenLIME, and report its round trip against the model");
    command->add_option("MODEL", args->model, "Model file written by vpe fit")->required();
    command->add_option("CAPTURE", args->capture, "The capture the model was fitted on")
        ->required();
    command->add_option("--out", args->out, "Folder to write (replaced as a whole)")->required();
    command->add_option("--resolution", args->resolution, "Light grid side R (R x R directions)")
        ->capture_default_str()
        ->check(CLI::Range(2, 64));
    command->add_option("--planes", args->planes, "PCA planes, a multiple of 3")
        ->capture_default_str();
    command->add_option("--quality", args->quality, "JPEG quality of the planes")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    command
        ->add_option("--grid", args->grid,
                     "Grid node values: the model under each node's light (nodes), or those "
                     "whose interpolation best matches a twice-as-fine grid (least-squares)")
        ->capture_default_str()
        ->check(CLI::IsMember({"nodes", "least-squares"}));
    addHeldOutOption(command, args->heldOut,
                     "Measure the round trip under every N-th light only (those vpe fit "
                     "--held-out N left out); default: all lights");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runExportRelight(*args); }; });
}

}  // namespace vpe::cli
