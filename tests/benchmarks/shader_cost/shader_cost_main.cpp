// SPDX-License-Identifier: MIT
// vpe_shader_cost: per-pixel ALU, SFU and texture cost of GLSL ES fragment shaders, counted on
// the SPIR-V a driver-like optimizer leaves, and the frame rates that bounds on a Pi 4 / Pi 5.
//   vpe_shader_cost [--json] [--pixels N] [--efficiency E] [--memory-share F]
//                   [--texture-format SAMPLER=FORMAT]... [--spirv DIR] SHADER.frag...
// --memory-share: the fraction of the board's memory rate the GPU is assumed to get (1).
// --spirv writes the optimized SPIR-V that was counted to DIR/NAME.spv (spirv-dis shows it).
// Bad input (unreadable file, GLSL that does not compile, bad option): one line on stderr,
// exit status 2.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "roofline.h"
#include "shader_analysis.h"
#include "shader_compiler.h"
#include "texture_formats.h"

namespace {

using vpe::shader_cost::ShaderReport;

struct Options {
    bool json = false;
    vpe::shader_cost::FrameWorkload workload;
    std::map<std::string, std::string> textureFormats;
    std::filesystem::path spirvFolder;
    std::vector<std::string> shaders;
};

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

double positiveNumber(const std::string& option, const std::string& text) {
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !(value > 0) || !std::isfinite(value)) {
        throw UsageError(option + " " + text + ": expected a positive number");
    }
    return value;
}

Options parseOptions(int argc, char** argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                throw UsageError(argument + ": missing value");
            }
            return argv[++i];
        };
        if (argument == "--json") {
            options.json = true;
        } else if (argument == "--pixels") {
            options.workload.shadedPixels = positiveNumber(argument, value());
        } else if (argument == "--efficiency") {
            options.workload.aluEfficiency = positiveNumber(argument, value());
            if (options.workload.aluEfficiency > 1) {
                throw UsageError("--efficiency: expected a fraction in (0, 1]");
            }
        } else if (argument == "--memory-share") {
            options.workload.memoryShare = positiveNumber(argument, value());
            if (options.workload.memoryShare > 1) {
                throw UsageError("--memory-share: expected a fraction in (0, 1]");
            }
        } else if (argument == "--texture-format") {
            const std::string assignment = value();
            const std::size_t equals = assignment.find('=');
            if (equals == std::string::npos || equals == 0 ||
                !vpe::shader_cost::bytesPerTexel(assignment.substr(equals + 1))) {
                throw UsageError("--texture-format " + assignment +
                                 ": expected SAMPLER=FORMAT with a sized GLES format (RGBA16F)");
            }
            options.textureFormats[assignment.substr(0, equals)] = assignment.substr(equals + 1);
        } else if (argument == "--spirv") {
            options.spirvFolder = value();
        } else if (argument == "--help" || argument == "-h") {
            std::printf(
                "usage: vpe_shader_cost [--json] [--pixels N] [--efficiency E] [--memory-share F]\n"
                "                       [--texture-format SAMPLER=FORMAT]... [--spirv DIR]\n"
                "                       SHADER.frag...\n");
            std::exit(0);
        } else if (argument.rfind("--", 0) == 0) {
            throw UsageError(argument + ": unknown option");
        } else {
            options.shaders.push_back(argument);
        }
    }
    if (options.shaders.empty()) {
        throw UsageError("no shader given (vpe_shader_cost --help)");
    }
    return options;
}

void printTable(const std::vector<ShaderReport>& reports, const Options& options) {
    const vpe::shader_cost::GpuPeaks pi4 = vpe::shader_cost::raspberryPi4();
    const vpe::shader_cost::GpuPeaks pi5 = vpe::shader_cost::raspberryPi5();
    std::printf(
        "Per shaded pixel, most expensive path through main (FLOPs include int_ops;\n"
        "flop_eq = FLOPs + 4 x SFU; bytes = texture bytes requested where the sampler's\n"
        "format is known, bilinear = 4 texels; + when some fetches have no format;\n"
        "mem_B = bytes from and to memory: a texel a fetch, none from cached tables,\n"
        "the outputs' texels; fps = the lower of the operations' and the bytes' bounds):\n\n");
    std::printf("%-16s %8s %8s %6s %8s %8s %8s %6s %9s %9s %8s\n", "shader", "FLOPs", "int_ops",
                "SFU", "flop_eq", "fetches", "bytes", "mem_B", "pi4_fps", "pi5_fps", "dyn.loop");
    for (const ShaderReport& report : reports) {
        const auto& cost = report.perPixel;
        const std::string bytes =
            std::to_string(cost.textureBytes) + (cost.fetchesWithoutFormat > 0 ? "+" : "");
        std::printf("%-16s %8lld %8lld %6lld %8lld %8lld %8s %6lld %9.2f %9.2f %8s\n",
                    report.name.c_str(), static_cast<long long>(cost.flops()),
                    static_cast<long long>(cost.intOps), static_cast<long long>(cost.sfu),
                    static_cast<long long>(cost.flopEquivalent()),
                    static_cast<long long>(cost.textureFetches), bytes.c_str(),
                    static_cast<long long>(cost.memoryBytes()),
                    estimateFrame(cost, pi4, options.workload).framesPerSecond,
                    estimateFrame(cost, pi5, options.workload).framesPerSecond,
                    report.hasDynamicLoops ? "yes" : "no");
    }
    std::printf(
        "\nFrame bounds at %.3g shaded pixels, ALU at %.0f%% of peak, the GPU getting %.0f%% of "
        "the memory rate:\n",
        options.workload.shadedPixels, 100 * options.workload.aluEfficiency,
        100 * options.workload.memoryShare);
    for (const vpe::shader_cost::GpuPeaks& gpu : {pi4, pi5}) {
        std::printf(
            "  %s: ALU %.1f GFLOPS peak, TMU %.2f G lookups/s (assumed), memory %.2f GB/s (%s)\n",
            gpu.name.c_str(), gpu.aluFlops / 1e9, gpu.textureLookups / 1e9, gpu.memoryBytes / 1e9,
            gpu.memorySource.c_str());
        for (const ShaderReport& report : reports) {
            const auto estimate = estimateFrame(report.perPixel, gpu, options.workload);
            const double slowest =
                std::max({estimate.aluSeconds, estimate.textureSeconds, estimate.memorySeconds});
            std::printf(
                "    %-16s ALU %7.1f ms, TMU %7.1f ms, memory %7.1f ms -> %.2f fps (%s-bound)\n",
                report.name.c_str(), 1e3 * estimate.aluSeconds, 1e3 * estimate.textureSeconds,
                1e3 * estimate.memorySeconds, estimate.framesPerSecond,
                slowest == estimate.aluSeconds       ? "ALU"
                : slowest == estimate.textureSeconds ? "TMU"
                                                     : "memory");
        }
    }
    for (const ShaderReport& report : reports) {
        if (report.perPixel.fetchesWithoutFormat > 0) {
            std::printf("%s: %lld fetches from samplers without a declared format (not in bytes)\n",
                        report.name.c_str(),
                        static_cast<long long>(report.perPixel.fetchesWithoutFormat));
        }
        for (const auto& [opcode, count] : report.uncountedOpcodes) {
            std::printf("%s: SPIR-V opcode %u has no counting rule (%lld instructions, free)\n",
                        report.name.c_str(), opcode, static_cast<long long>(count));
        }
    }
}

nlohmann::json toJson(const std::vector<ShaderReport>& reports, const Options& options) {
    nlohmann::json shaders = nlohmann::json::array();
    for (const ShaderReport& report : reports) {
        const auto& cost = report.perPixel;
        const auto pi4 = estimateFrame(cost, vpe::shader_cost::raspberryPi4(), options.workload);
        const auto pi5 = estimateFrame(cost, vpe::shader_cost::raspberryPi5(), options.workload);
        shaders.push_back({
            {"name", report.name},
            {"flops", cost.flops()},
            {"int_ops", cost.intOps},
            {"sfu", cost.sfu},
            {"flop_eq", cost.flopEquivalent()},
            {"texture_fetches", cost.textureFetches},
            {"texture_bytes", cost.textureBytes},
            {"fetches_without_format", cost.fetchesWithoutFormat},
            {"memory_read_bytes", cost.memoryReadBytes},
            {"memory_write_bytes", cost.memoryWriteBytes},
            {"memory_bytes", cost.memoryBytes()},
            {"pi4_fps", pi4.framesPerSecond},
            {"pi4_compute_fps", pi4.computeFramesPerSecond},
            {"pi4_memory_fps", pi4.memoryFramesPerSecond},
            {"pi5_fps", pi5.framesPerSecond},
            {"pi5_compute_fps", pi5.computeFramesPerSecond},
            {"pi5_memory_fps", pi5.memoryFramesPerSecond},
            {"has_dynamic_loops", report.hasDynamicLoops},
        });
    }
    return {{"shaders", shaders}};
}

void writeSpirv(const std::filesystem::path& folder, const ShaderReport& report) {
    std::filesystem::create_directories(folder);
    const std::filesystem::path path = folder / (report.name + ".spv");
    std::ofstream stream(path, std::ios::binary);
    stream.write(reinterpret_cast<const char*>(report.spirv.data()),
                 static_cast<std::streamsize>(report.spirv.size() * sizeof(std::uint32_t)));
    if (!stream) {
        throw std::runtime_error(path.string() + ": cannot write");
    }
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options options = parseOptions(argc, argv);
        const vpe::shader_cost::ShaderCompiler compiler;
        std::vector<ShaderReport> reports;
        for (const std::string& shader : options.shaders) {
            reports.push_back(
                vpe::shader_cost::analyzeShaderFile(compiler, shader, options.textureFormats));
        }
        if (!options.spirvFolder.empty()) {
            for (const ShaderReport& report : reports) {
                writeSpirv(options.spirvFolder, report);
            }
        }
        printTable(reports, options);
        if (options.json) {
            std::printf("%s\n", toJson(reports, options).dump().c_str());
        }
        return 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_shader_cost: %s\n", error.what());
        return 2;
    }
}
