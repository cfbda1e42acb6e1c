// SPDX-License-Identifier: MIT
// vpe projector-ring --count N [--distance D] [--elevation E] [--size WxH] [--fov F] --out DIR
// Calibration files for N projectors evenly around the object, aimed at it: a show to rehearse
// with the simulator before a single projector is hung (docs/multi-projector.md).
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/scene_settings.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct ProjectorRingArguments {
    int count = 3;
    double distance = 0.6, elevation = 15, fov = 30, azimuth = 0;
    std::string size = "1920x1080", target = "0,0.075,0", out;
    bool json = false;
};

void runProjectorRing(const ProjectorRingArguments& args) {
    if (args.count < 1 || args.count > 32) {
        throw common::InputError("--count: expected 1 to 32 projectors");
    }
    if (!(args.distance > 0) || !std::isfinite(args.distance)) {
        throw common::InputError("--distance: expected metres > 0");
    }
    if (!(args.elevation > -80 && args.elevation < 80)) {
        throw common::InputError("--elevation: expected degrees within ±80");
    }
    if (!(args.fov > 0 && args.fov < 180)) {
        throw common::InputError("--fov: expected degrees in (0, 180)");
    }
    const SizeArgument size = parseSizeArgument(args.size, "--size", 8192);
    const auto target = scene::parsePosition(args.target, "--target");
    common::AtomicFolder folder(args.out, "ring.json", "vpe projector-ring");
    nlohmann::json json;
    json["projectors"] = nlohmann::json::array();
    const double e = args.elevation * std::numbers::pi / 180;
    for (int i = 0; i < args.count; ++i) {
        const double azimuth = args.azimuth + 360.0 * i / args.count;
        const double a = azimuth * std::numbers::pi / 180;
        const proto::Vec3d eye{target.x + args.distance * std::sin(a) * std::cos(e),
                               target.y + args.distance * std::sin(e),
                               target.z + args.distance * std::cos(a) * std::cos(e)};
        const scene::ProjectorCalibration projector =
            scene::projectorLookingAt(size.width, size.height, args.fov, eye, target);
        const std::string name = "projector" + std::to_string(i + 1) + ".yml";
        scene::writeProjectorCalibration(projector, folder.temporaryPath() / name);
        json["projectors"].push_back(
            {{"file", name}, {"azimuth", azimuth}, {"position", {eye.x, eye.y, eye.z}}});
    }
    proto::writeTextFileAtomically(folder.temporaryPath() / "ring.json", json.dump(2) + "\n");
    folder.commit();
    std::fprintf(stderr, "%s: %d projectors %.2f m from the object, %.0f° up, every %.0f°\n",
                 args.out.c_str(), args.count, args.distance, args.elevation, 360.0 / args.count);
    if (args.json) {
        printJson(json.dump());
    }
}

}  // namespace

void addProjectorRingCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ProjectorRingArguments>();
    CLI::App* command = app.add_subcommand(
        "projector-ring",
        "Calibration files for projectors evenly around the object, to rehearse a show");
    command->add_option("--count", args->count, "Projectors")->capture_default_str();
    command->add_option("--distance", args->distance, "From the target (m)")->capture_default_str();
    command->add_option("--elevation", args->elevation, "Above the target (degrees)")
        ->capture_default_str();
    command->add_option("--azimuth", args->azimuth, "The first one's (degrees; 0 = +z, the front)")
        ->capture_default_str();
    command->add_option("--size", args->size, "Resolution WxH")->capture_default_str();
    command->add_option("--fov", args->fov, "Vertical field of view (degrees)")
        ->capture_default_str();
    command->add_option("--target", args->target, "What they aim at, x,y,z (m, object frame)")
        ->capture_default_str();
    command->add_option("--out", args->out, "Folder for projectorN.yml and ring.json")->required();
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runProjectorRing(*args); }; });
}

}  // namespace vpe::cli
