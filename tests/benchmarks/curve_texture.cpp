// SPDX-License-Identifier: MIT
// The curve benchmarks' arguments, scratch folder and main.
#include "curve_texture.h"

#include <cstdio>
#include <exception>
#include <string>
#include <system_error>

#include <unistd.h>

namespace vpe::benchmarks {

std::optional<CurveArguments> parseCurveArguments(int argc, char** argv) {
    CurveArguments arguments;
    arguments.options.settings.viewerPosition = {0.0f, 0.075f, 1.0f};  // vpe bake's default
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        if (argument == "--quilt" && i + 1 < argc) {
            arguments.options.quilt = argv[++i];
        } else if (argument == "--preset" && i + 1 < argc) {
            arguments.options.presets.push_back({"curve", argv[++i]});
        } else if (argument == "--texture" && i + 1 < argc) {
            arguments.options.texture = argv[++i];
        } else if (argument == "--json") {
            arguments.json = true;
        } else {
            std::fprintf(
                stderr, "usage: %s (--quilt DIR --preset WEIGHTS | --texture MODEL.exr) [--json]\n",
                argv[0]);
            return std::nullopt;
        }
    }
    return arguments;
}

CurveWorkFolder::CurveWorkFolder(const std::string& prefix)
    : path_(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
}

CurveWorkFolder::~CurveWorkFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
}

int runCurve(int argc, char** argv, const std::string& workPrefix, const Curve& curve) {
    const std::optional<CurveArguments> arguments = parseCurveArguments(argc, argv);
    if (!arguments) {
        return 2;
    }
    const CurveWorkFolder work(workPrefix);
    try {
        curve(*arguments, work);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 2;
    }
    return 0;
}

}  // namespace vpe::benchmarks
