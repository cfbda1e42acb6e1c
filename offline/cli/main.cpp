// SPDX-License-Identifier: MIT
// vpe: the offline tools. Bad input (proto::InputError, and every error derived from it: a
// bundle, a scan manifest, a scene file, ...) ends with one line on stderr and exit status 2.
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "vpe/fit/normal_equations.h"
#include "vpe/proto/input_error.h"

#include "cli/commands.h"

namespace vpe::cli {

void printJson(const std::string& json) {
    std::printf("%s\n", json.c_str());
}

}  // namespace vpe::cli

int main(int argc, char** argv) {
    CLI::App app{"vpe: capture to Fourier BRDF model, texture, bake (see README.md)", "vpe"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "vpe 0.1.0");
    vpe::cli::Action action;
    vpe::cli::addFitCommand(app, action);
    vpe::cli::addEvalCommand(app, action);
    vpe::cli::addSweepCommand(app, action);
    vpe::cli::addNormalsCommand(app, action);
    vpe::cli::addSynthCommand(app, action);
    vpe::cli::addSegmentCommand(app, action);
    vpe::cli::addQuiltCommand(app, action);
    vpe::cli::addRelightCommand(app, action);
    vpe::cli::addExportRelightCommand(app, action);
    vpe::cli::addComposeCommand(app, action);
    vpe::cli::addWeightsCommand(app, action);
    vpe::cli::addQuiltQualityCommand(app, action);
    vpe::cli::addBakeCommand(app, action);
    vpe::cli::addRenderCommand(app, action);
    vpe::cli::addInfoCommand(app, action);
    vpe::cli::addTransferCommand(app, action);
    vpe::cli::addSynthProcamCommand(app, action);
    vpe::cli::addImportGrayCodeCommand(app, action);
    vpe::cli::addCalibrateCommand(app, action);
    vpe::cli::addScanCommand(app, action);
    vpe::cli::addRadiometryCommand(app, action);
    vpe::cli::addProjectorRingCommand(app, action);
    vpe::cli::addShowCheckCommand(app, action);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        // Help and version requests arrive as "errors" with exit code 0.
        if (error.get_exit_code() == 0) {
            return app.exit(error);
        }
        std::fprintf(stderr, "vpe: %s (see vpe --help)\n", error.what());
        return 2;
    }
    try {
        // The fit's SIMD kernels on another target than the best this CPU runs
        // (docs/fitting.md): to measure here what another machine would run.
        if (const char* simd = std::getenv("VPE_SIMD"); simd != nullptr && *simd != '\0') {
            vpe::fit::restrictKernelTarget(simd);
        }
        action();
    } catch (const vpe::proto::InputError& error) {
        std::fprintf(stderr, "vpe: %s\n", error.what());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "vpe: out of memory\n");
        return 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe: internal error: %s\n", error.what());
        return 1;
    }
    return 0;
}
