// SPDX-License-Identifier: MIT
// vpe relight MODEL.exr --out picture.png [--light x,y,z] [--exposure E]
#include <cmath>
#include <cstdio>
#include <memory>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/srgb.h"

#include "cli/commands.h"

namespace vpe::cli {

namespace {

struct Arguments {
    std::string model;
    std::string out;
    std::vector<double> light{0.5, 0.5, 0.707};
    double exposure = 1.0;
};

// What `vpe relight` does once its options are parsed.
void runRelight(const Arguments& args) {
    const proto::Vec3d light{args.light[0], args.light[1], args.light[2]};
    const double length = std::sqrt(proto::dot(light, light));
    if (!(length > 1e-9) || !std::isfinite(length)) {
        throw common::InputError("--light must be a non-zero direction");
    }
    const proto::Vec3d toLight{light.x / length, light.y / length, light.z / length};
    model::ModelReader reader(args.model);
    const model::ModelInfo& info = reader.info();
    model::ModelRows rows;
    reader.readRows(0, info.height, rows);
    std::vector<float> pixels(static_cast<std::size_t>(info.width) * info.height * 3, 0.0f);
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
                const double v = args.exposure * proto::evaluateFourierBrdf(
                                                     rows.coefficientsAt(y, x, c), info.harmonics,
                                                     angles.cosThetaD, angles.cosThetaS);
                pixels[p * 3 + static_cast<std::size_t>(c)] =
                    static_cast<float>(proto::linearToSrgb(std::clamp(v, 0.0, 1.0)));
            }
        }
    }
    image::writeImage(args.out, info.width, info.height, 3, pixels, image::PixelFormat::kUint8);
}

}  // namespace

void addRelightCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<Arguments>();
    CLI::App* command = app.add_subcommand(
        "relight",
        "Render a model or texture under one directional light, seen from +z (sRGB PNG)");
    command->add_option("MODEL", args->model, "Model or texture file (.exr)")->required();
    command->add_option("--out", args->out, "Picture to write")->required();
    command->add_option("--light", args->light, "Direction towards the light x,y,z")
        ->delimiter(',')
        ->expected(3);
    command->add_option("--exposure", args->exposure, "Multiplier before sRGB encoding")
        ->capture_default_str();
    command->callback([args, &action] { action = [args] { runRelight(*args); }; });
}

}  // namespace vpe::cli
