// SPDX-License-Identifier: MIT
// vpe fit CAPTURE --out MODEL.exr
#include <cmath>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/fit/capture_fitter.h"
#include "vpe/fit/normal_equations.h"
#include "vpe/model/rti_basis.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/storage_option.h"

namespace vpe::cli {

namespace {

struct FitArguments {
    std::string capture;
    std::string out;
    int harmonics = proto::kDefaultHarmonics;
    double lambda = proto::kDefaultLambda;
    std::string normals;
    int threads = 0;
    std::string precision = "auto";
    std::string model = "paper";
    int heldOut = 0;
    std::string storage;
    std::string relief = "detail";
    std::string response = "auto";
    double macroSigma = 0;
    bool regularizationGiven = false;
    bool json = false;
    bool noPreview = false;
    bool fallBack = false;
};

// The blocked lights' calibration: how many lights it found blocked (none: not adopted), the
// lowest intensity, and the held-out figures that decided it (per-image RMS, 8-bit levels).
nlohmann::json lightIntensitiesJson(const fit::FitReport& report) {
    int blocked = 0;
    double lowest = 1;
    for (const capture::LightIntensity& entry : report.calibration.lightIntensities) {
        blocked += entry.intensity < 1 ? 1 : 0;
        lowest = std::min(lowest, entry.intensity);
    }
    return {{"blocked", blocked},
            {"lowest", lowest},
            {"heldout_image_rms", report.lightIntensityRms},
            {"heldout_image_rms_as_stated", report.lightIntensityStatedRms}};
}

// What `vpe fit` does once its options are parsed.
void runFit(const FitArguments& args) {
    fit::FitOptions options;
    options.harmonics = args.harmonics;
    options.lambda = args.lambda;
    options.threads = common::resolveThreadCount(args.threads);
    options.precision = args.precision == "fast"    ? fit::FitPrecision::kFast
                        : args.precision == "exact" ? fit::FitPrecision::kExact
                                                    : fit::FitPrecision::kAuto;
    if (!args.normals.empty()) {
        options.normals = args.normals;
    }
    options.writePreview = !args.noPreview;
    options.storage = parseStorage(args.storage).value_or(model::ModelStorage::kHalf);
    options.relief = args.relief == "coefficients" ? fit::ReliefMode::kInCoefficients
                                                   : fit::ReliefMode::kDetailMap;
    options.calibrateResponse = args.response == "auto";
    options.fallBackToClassicBasis = args.fallBack;
    if (!(args.macroSigma >= 0) || !std::isfinite(args.macroSigma)) {
        throw common::InputError("--macro-sigma must be a number of pixels ≥ 0");
    }
    if (args.macroSigma > 0) {
        options.macroSigma = args.macroSigma;
    }
    options.variant = args.model == "extended" ? fit::ModelVariant::kExtended
                      : args.model == "paper"  ? fit::ModelVariant::kPaper
                                               : fit::ModelVariant::kRti;
    if (options.variant == fit::ModelVariant::kRti) {
        options.rtiBasis = *model::RtiBasis::parse(args.model);
        options.writePreview = false;  // the preview relights a BRDF
    }
    // The extended model picks M and λ by held-out validation unless they are given.
    options.selectRegularization =
        options.variant == fit::ModelVariant::kExtended && !args.regularizationGiven;
    capture::Capture capture = capture::openCapture(args.capture);
    if (args.heldOut > 0) {
        capture = capture::selectHeldOutLights(capture, args.heldOut, false);
    }
    const fit::FitReport report = fit::fitCapture(capture, options, args.out);
    if (options.variant == fit::ModelVariant::kRti) {
        std::fprintf(stderr,
                     "fitted %zu of %zu pixels from %d images (%s on stored values) in "
                     "%.2f s; mean residual RMS %.4f\n",
                     report.validPixels, report.pixels, report.images,
                     options.rtiBasis.name().c_str(), report.totalSeconds, report.meanRms);
    } else {
        std::fprintf(stderr,
                     "fitted %zu of %zu pixels from %d images (M = %d, λ = %g, normals: "
                     "%s) in %.2f s; mean residual RMS %.4f\n",
                     report.validPixels, report.pixels, report.images, report.harmonics,
                     report.lambda, report.normalsSource.c_str(), report.totalSeconds,
                     report.meanRms);
    }
    if (options.variant == fit::ModelVariant::kExtended) {
        std::fprintf(
            stderr,
            "selected: response %s, field of view %.1f°, light distance %.2f "
            "half-widths, M = %d, λ = %g (held-out RMS %.3f vs %.3f as stated), T ridge %g "
            "(held-out RMS %.3f with T), light intensities %s, normals %s (%.2f s)\n",
            report.calibration.responseGamma > 0
                ? ("gamma " + std::to_string(report.calibration.responseGamma).substr(0, 4)).c_str()
                : "as stated",
            report.calibration.fieldOfViewDegrees, report.calibration.lightDistance,
            report.harmonics, report.lambda, report.calibratedRms, report.uncalibratedRms,
            report.transportRidge, report.transportRms,
            report.calibration.lightIntensities.empty() ? "as stated" : "some blocked",
            report.normalSearchDegrees > 0 ? "refined by the fit" : "as estimated or given",
            report.calibrationSeconds);
    }
    if (!report.betterClassicBasis.empty()) {
        for (const fit::ClassicBasisScore& basis : report.classicBases) {
            if (basis.basis == report.betterClassicBasis) {
                std::fprintf(
                    stderr,
                    "%s predicts this capture's own held-out training lights better than "
                    "the extended model (every fold: %.2f against %.2f levels, the images' "
                    "mean RMS)%s\n",
                    basis.basis.c_str(), basis.score.imageMean, report.extendedEveryFold.imageMean,
                    report.fellBackToClassicBasis
                        ? ": written instead (--fall-back)"
                        : "; --fall-back writes it instead (not a BRDF: nothing in it "
                          "transfers to another shape)");
            }
        }
    }
    if (args.json) {
        nlohmann::json json;
        json["model_variant"] = args.model;
        if (options.variant == fit::ModelVariant::kExtended) {
            json["calibration"] = {{"field_of_view_degrees", report.calibration.fieldOfViewDegrees},
                                   {"light_distance", report.calibration.lightDistance},
                                   {"response_gamma", report.calibration.responseGamma},
                                   {"response_heldout_rms", report.responseRms},
                                   {"srgb_response_heldout_rms", report.statedResponseRms},
                                   {"normals_under_srgb", report.normalsUnderStatedResponse},
                                   {"transport_ridge", report.transportRidge},
                                   {"transport_heldout_rms", report.transportRms},
                                   {"normal_search_degrees", report.normalSearchDegrees},
                                   {"light_intensities", lightIntensitiesJson(report)},
                                   {"heldout_rms", report.calibratedRms},
                                   {"uncalibrated_heldout_rms", report.uncalibratedRms},
                                   {"seconds", report.calibrationSeconds}};
        }
        if (!report.classicBases.empty()) {
            nlohmann::json bases = nlohmann::json::array();
            for (const fit::ClassicBasisScore& basis : report.classicBases) {
                bases.push_back({{"basis", basis.basis},
                                 {"heldout_rms", basis.score.pooled},
                                 {"image_rms", basis.score.imageMean}});
            }
            json["classic_bases"] = {{"every_fold", bases},
                                     {"extended",
                                      {{"heldout_rms", report.extendedEveryFold.pooled},
                                       {"image_rms", report.extendedEveryFold.imageMean}}},
                                     {"better", report.betterClassicBasis},
                                     {"written_instead", report.fellBackToClassicBasis}};
        }
        if (!report.searchStageSeconds.empty()) {
            nlohmann::json stages = nlohmann::json::array();
            for (const fit::SearchStageTime& stage : report.searchStageSeconds) {
                stages.push_back({{"stage", stage.stage}, {"seconds", stage.seconds}});
            }
            json["calibration"]["stage_seconds"] = stages;
        }
        if (!report.transportTrials.empty()) {
            nlohmann::json trials = nlohmann::json::array();
            for (const fit::TransportRidgeTrial& trial : report.transportTrials) {
                trials.push_back({{"ridge", trial.ridge}, {"rms", trial.rms}});
            }
            json["calibration"]["transport_trials"] = trials;
        }
        json["pixels"] = report.pixels;
        json["valid_pixels"] = report.validPixels;
        json["images"] = report.images;
        json["width"] = report.width;
        json["height"] = report.height;
        if (options.variant == fit::ModelVariant::kRti || report.fellBackToClassicBasis) {
            json["basis"] =
                report.fellBackToClassicBasis ? report.betterClassicBasis : options.rtiBasis.name();
        } else {
            json["harmonics"] = report.harmonics;
            json["lambda"] = report.lambda;
            // An RTI fit is on the stored values: no relief is measured or written.
            json["relief"] = args.relief;
            json["macro_sigma"] = report.macroSigma;
            json["mean_relief_degrees"] = report.meanReliefDegrees;
        }
        json["normals"] = report.normalsSource;
        json["mean_rms"] = report.meanRms;
        json["model"] = args.out;
        if (!report.preview.empty()) {
            json["preview"] = report.preview.string();
        }
        json["simd"] = fit::activeKernelTargetName();  // VPE_SIMD, or the best this CPU runs
        json["seconds"] = {{"decode", report.decodeSeconds},
                           {"normals", report.normalsSeconds},
                           {"fit", report.fitSeconds},
                           {"write", report.writeSeconds},
                           {"total", report.totalSeconds}};
        printJson(json.dump());
    }
}

}  // namespace

void addFitCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<FitArguments>();
    CLI::App* command = app.add_subcommand(
        "fit", "Fit a per-pixel Fourier BRDF to a capture and write the model (OpenEXR)");
    command
        ->add_option("CAPTURE", args->capture,
                     "Folder with a .lp file or capture.json, or the path of either")
        ->required();
    command->add_option("--out", args->out, "Model file to write (.exr)")->required();
    CLI::Option* harmonicsOption =
        command
            ->add_option("--harmonics", args->harmonics,
                         "Harmonics M (2M + 2 coefficients); extended model: chosen by "
                         "held-out validation unless given")
            ->capture_default_str();
    CLI::Option* lambdaOption =
        command->add_option("--lambda", args->lambda, "Smoothness weight λ (as --harmonics)")
            ->capture_default_str();
    command->add_option("--normals", args->normals,
                        "Normal map to use instead of the capture's own or photometric stereo");
    addThreadsOption(command, args->threads);
    addChoiceOption(command, "--precision", args->precision,
                    "auto (exact when λ < 1e-3), fast (float sums) or exact (double sums)",
                    {"auto", "fast", "exact"});
    command
        ->add_option("--model", args->model,
                     "paper: eq. 16-19 under the capture's stated geometry; extended: also "
                     "calibrate camera field of view and light distance (docs/extended-model.md); "
                     "ptm6, ptm10, hsh4, hsh9, hsh16, hsh25: a classic RTI basis fitted on the "
                     "stored image values, for comparison (not a BRDF; docs/rti-bases.md)")
        ->check([](const std::string& model) {
            return model == "paper" || model == "extended" || model::RtiBasis::parse(model)
                       ? std::string()
                       : "expected paper, extended, ptm6, ptm10, hsh4, hsh9, hsh16 or hsh25, "
                         "found '" +
                             model + "'";
        })
        ->capture_default_str();
    addHeldOutOption(command, args->heldOut,
                     "Leave every N-th light out (positions N-1, 2N-1, ... of the capture): the "
                     "RTI benchmarks' protocol; score them with vpe eval --held-out N");
    addStorageOption(command, args->storage, "half");
    addChoiceOption(command, "--relief", args->relief,
                    "detail: fit the per-pixel normals and write the relief as a detail normal "
                    "map; coefficients: fit the macro shape's normals, the coefficients absorb "
                    "the relief (docs/transfer-fidelity.md)",
                    {"detail", "coefficients"});
    addChoiceOption(command, "--response", args->response,
                    "extended model, 8-bit images of unstated encoding: auto calibrates the "
                    "camera's response (a power law, by held-out validation; many RTI cameras "
                    "store radiance nearly linearly); srgb keeps the sRGB decoding",
                    {"auto", "srgb"});
    command->add_option("--macro-sigma", args->macroSigma,
                        "σ (pixels) of the regression window giving the macro shape (0: 1/8 of the "
                        "larger side)");
    command->add_flag("--no-preview", args->noPreview, "Do not write MODEL.preview.png");
    command->add_flag("--fall-back", args->fallBack,
                      "extended model: where a classic RTI basis (PTM-6, HSH-9, HSH-16) predicts "
                      "the capture's own held-out training lights better (every fold), write that "
                      "basis instead (without it the fit only says so)");
    addJsonFlag(command, args->json);
    command->callback([args, &action, harmonicsOption, lambdaOption] {
        args->regularizationGiven = harmonicsOption->count() > 0 || lambdaOption->count() > 0;
        action = [args] { runFit(*args); };
    });
}

}  // namespace vpe::cli
