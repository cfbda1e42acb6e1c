// SPDX-License-Identifier: MIT
// vpe relight MODEL.exr --out picture.png [--light x,y,z] [--exposure E] [--as captured|material]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/eval/capture_predictor.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/srgb.h"

#include "cli/commands.h"

namespace vpe::cli {

namespace {

struct RelightArguments {
    std::string model;
    std::string out;
    std::vector<double> light{0.5, 0.5, 0.707};
    double exposure = 1.0;
    std::string as = "captured";
};

// The picture as the capture's camera would have recorded it under one more light from
// `toLight`: what `vpe eval` predicts (eval::CapturePredictor), so the model's calibrated camera,
// light distance, response and light transport all apply. The light is unobstructed, as
// `vpe export-relight` relights: a lamp the rig blocked (the calibration's light
// intensities) belongs to the rig, not to the object. Invalid pixels stay black.
void renderAsCaptured(const model::ModelInfo& fitted, const model::ModelRows& rows,
                      const proto::Vec3d& toLight, double exposure, std::vector<float>& pixels) {
    model::ModelInfo info = fitted;
    info.calibration.lightIntensities.clear();
    // A capture as an RTI light file states one: directional light, orthographic camera,
    // encoding left to the images. The predictor puts the model's calibration in its place.
    capture::Capture capture;
    capture.source = fitted.capture;
    capture::CaptureImage image;
    image.light = toLight;
    image.intensity = exposure;
    capture.images = {image};
    const eval::CapturePredictor predictor(info, capture, storedTransfer(capture, true));
    for (int y = 0; y < info.height; ++y) {
        for (int x = 0; x < info.width; ++x) {
            const std::size_t p = rows.pixel(y, x);
            if (!rows.valid[p]) {
                continue;
            }
            const std::array<double, 3> rgb = predictor.predict(rows, y, x, y, 0);
            for (int c = 0; c < 3; ++c) {
                pixels[p * 3 + static_cast<std::size_t>(c)] =
                    static_cast<float>(rgb[static_cast<std::size_t>(c)]);
            }
        }
    }
}

// The material alone: the Fourier BRDF under a directional light, seen from +z, sRGB — what
// the projector and the bake render, without the capture's camera, response or transport.
void renderMaterial(const model::ModelInfo& info, const model::ModelRows& rows,
                    const proto::Vec3d& toLight, double exposure, std::vector<float>& pixels) {
    for (int y = 0; y < info.height; ++y) {
        for (int x = 0; x < info.width; ++x) {
            const std::size_t p = rows.pixel(y, x);
            if (!rows.valid[p]) {
                continue;
            }
            const proto::Vec3d n{rows.normal[p * 3], rows.normal[p * 3 + 1],
                                 rows.normal[p * 3 + 2]};
            const auto angles = proto::reflectionAngles(n, toLight, proto::Vec3d{0, 0, 1});
            for (int c = 0; c < 3; ++c) {
                const double v = exposure * proto::evaluateFourierBrdf(
                                                rows.coefficientsAt(y, x, c), info.harmonics,
                                                angles.cosThetaD, angles.cosThetaS);
                pixels[p * 3 + static_cast<std::size_t>(c)] =
                    static_cast<float>(proto::linearToSrgb(std::clamp(v, 0.0, 1.0)));
            }
        }
    }
}

// One line saying what the picture shows: a calibrated model's picture and the material's
// differ by 10 dB on a real capture, so neither is left to be guessed.
std::string describe(const model::ModelInfo& info, bool asCaptured) {
    if (!asCaptured) {
        return "the material alone (Fourier BRDF, directional light, seen from +z, sRGB)";
    }
    const capture::GeometryCalibration& c = info.calibration;
    char camera[64] = "orthographic camera";
    if (c.fieldOfViewDegrees > 0) {
        std::snprintf(camera, sizeof camera, "%.3g° perspective camera", c.fieldOfViewDegrees);
    }
    char light[64] = "directional light";
    if (c.lightDistance > 0) {
        std::snprintf(light, sizeof light, "light at %.3g image half-widths", c.lightDistance);
    }
    char response[32] = "sRGB";
    if (c.responseGamma > 0) {
        std::snprintf(response, sizeof response, "gamma %.3g", c.responseGamma);
    }
    return std::string("as the capture's camera recorded it (") + camera + ", " + light +
           ", response " + response + (info.hasTransport() ? ", light transport T)" : ")");
}

// What `vpe relight` does once its options are parsed.
void runRelight(const RelightArguments& args) {
    const proto::Vec3d light{args.light[0], args.light[1], args.light[2]};
    const double length = std::sqrt(proto::dot(light, light));
    if (!(length > 1e-9) || !std::isfinite(length)) {
        throw common::InputError("--light must be a non-zero direction");
    }
    if (!(args.exposure > 0) || !std::isfinite(args.exposure)) {
        throw common::InputError("--exposure " + std::to_string(args.exposure) +
                                 " must be positive");
    }
    const proto::Vec3d toLight{light.x / length, light.y / length, light.z / length};
    model::ModelReader reader(args.model);
    const model::ModelInfo& info = reader.info();
    model::ModelRows rows;
    reader.readRows(0, info.height, rows);
    std::vector<float> pixels(static_cast<std::size_t>(info.width) * info.height * 3, 0.0f);
    const bool asCaptured = args.as == "captured";
    if (asCaptured) {
        renderAsCaptured(info, rows, toLight, args.exposure, pixels);
    } else {
        renderMaterial(info, rows, toLight, args.exposure, pixels);
    }
    image::writeImage(args.out, info.width, info.height, 3, pixels, image::PixelFormat::kUint8);
    std::fprintf(stderr, "%s: %s\n", args.out.c_str(), describe(info, asCaptured).c_str());
}

}  // namespace

void addRelightCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<RelightArguments>();
    CLI::App* command = app.add_subcommand(
        "relight",
        "Render a model or texture under one light: as the capture's camera recorded it "
        "(calibrated camera, light distance, response, light transport; PNG)");
    command->add_option("MODEL", args->model, "Model or texture file (.exr)")->required();
    command->add_option("--out", args->out, "Picture to write")->required();
    command->add_option("--light", args->light, "Direction towards the light x,y,z")
        ->delimiter(',')
        ->expected(3);
    command->add_option("--exposure", args->exposure, "Multiplier of the light's irradiance")
        ->capture_default_str();
    command
        ->add_option("--as", args->as,
                     "captured: what vpe eval predicts the capture's camera sees (the model's "
                     "calibration and transport; the same as material for a model without "
                     "them); material: the Fourier BRDF alone, directional light, seen from +z, "
                     "sRGB")
        ->capture_default_str()
        ->check(CLI::IsMember({"captured", "material"}));
    command->callback([args, &action] { action = [args] { runRelight(*args); }; });
}

}  // namespace vpe::cli
