// SPDX-License-Identifier: MIT
// vpe import-graycode CAPTURE... --projector WxH [--step K] --out DIR
// Captures of OpenCV's GrayCodePattern (kamino410/procam-calibration's capture_*/graycode_NN.png)
// as vpe scan folders, one per capture under DIR, for vpe calibrate and vpe scan.
#include <chrono>
#include <cstdio>
#include <memory>
#include <set>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/seconds_since.h"
#include "vpe/structured_light/graycode_import.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

struct ImportGrayCodeArguments {
    std::vector<std::string> captures;
    std::string projector, out;
    int step = 1;
    bool json = false;
};

// The capture folder's own name ("capture_0" for "data/capture_0/"): its scan folder's under DIR.
std::string captureName(const std::string& capture) {
    std::filesystem::path path = std::filesystem::absolute(capture).lexically_normal();
    if (path.filename().empty()) {
        path = path.parent_path();
    }
    return path.filename().string();
}

void runImportGrayCode(const ImportGrayCodeArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const SizeArgument size = parseSizeArgument(args.projector, "--projector");
    const structured_light::GrayCodeProjector projector{size.width, size.height, args.step};
    // Each capture keeps its folder's name under DIR; two of one name would overwrite.
    std::set<std::string> names;
    for (const std::string& capture : args.captures) {
        const std::string name = captureName(capture);
        if (name.empty() || !names.insert(name).second) {
            throw common::InputError(
                capture, "its folder name '" + name + "' is not unique among the captures");
        }
    }
    // The whole DIR or nothing: a bad capture leaves no partial output.
    const std::string first = captureName(args.captures.front());
    common::AtomicFolder folder(args.out, std::filesystem::path(first) / proto::kScanManifestName,
                                "vpe import-graycode");
    nlohmann::json scans = nlohmann::json::array();
    for (const std::string& capture : args.captures) {
        const std::string name = captureName(capture);
        const proto::ScanManifest manifest = structured_light::importGrayCodeCapture(
            capture, projector, folder.temporaryPath() / name);
        scans.push_back({{"capture", capture},
                         {"scan", (std::filesystem::path(args.out) / name).string()},
                         {"images", manifest.images.size()},
                         {"camera", {manifest.camera.width, manifest.camera.height}}});
    }
    folder.commit();
    const double seconds = common::secondsSince(start);
    std::fprintf(stderr,
                 "%s: %zu scan folders of %zu images each (%dx%d projector, step %d) in %.2f s\n",
                 args.out.c_str(), args.captures.size(), scans.front()["images"].get<std::size_t>(),
                 size.width, size.height, args.step, seconds);
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        json["scans"] = scans;
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

}  // namespace

void addImportGrayCodeCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<ImportGrayCodeArguments>();
    CLI::App* command = app.add_subcommand(
        "import-graycode",
        "Turn OpenCV GrayCodePattern captures (procam-calibration's capture_*/graycode_NN.png) "
        "into vpe scan folders");
    command
        ->add_option("captures", args->captures,
                     "Capture folders of graycode_NN.png (or .jpg, .tif; 8- or 16-bit): column "
                     "bits (most significant first, each followed by its inverse), row bits, "
                     "white, black")
        ->required();
    command
        ->add_option("--projector", args->projector,
                     "The projector's size WxH the patterns were made for, e.g. 1024x768")
        ->required();
    command
        ->add_option("--step", args->step,
                     "Projector pixels per code along each axis (the tool's graycode step)")
        ->capture_default_str();
    command->add_option("--out", args->out, "Folder to write: one scan folder per capture")
        ->required();
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runImportGrayCode(*args); }; });
}

}  // namespace vpe::cli
