// SPDX-License-Identifier: MIT
// vpe_noise_sweep_plot SWEEP.json --out DIR
//
// The plots of scripts/real-procam-report.sh's noise sweep: a JSON array of levels, each
// {"output": "gamma8" | "linear10", "full_well": e⁻, "coverage": share of the lit, unshadowed
// camera pixels decoded, "wrong_code_share", "wrong_decode_share", "coarse_share",
// "depth_rms_mm"}; writes
// DIR/noise-coverage.svg (the share decoded), DIR/noise-wrong.svg (decoded more than a pixel
// off among those placed finer than a pixel, outside their own precision, and placed by a Gray
// bin alone) and DIR/noise-depth.svg (depth RMS), each against the
// full well.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/plot/svg_line_plot.h"

namespace {

struct Curve {
    std::vector<double> fullWell, coverage, wrongCode, wrongDecode, coarse, depth;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4 || std::string(argv[2]) != "--out") {
        std::fprintf(stderr, "usage: vpe_noise_sweep_plot SWEEP.json --out DIR\n");
        return 2;
    }
    std::ifstream input(argv[1]);
    nlohmann::json sweep;
    try {
        input >> sweep;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s: %s\n", argv[1], error.what());
        return 2;
    }
    std::map<std::string, Curve> curves;
    for (const nlohmann::json& level : sweep) {
        Curve& c = curves[level.at("output").get<std::string>()];
        // log10 of the full well: the sweep spans 400 to 20,000 electrons.
        c.fullWell.push_back(std::log10(level.at("full_well").get<double>()));
        c.coverage.push_back(100 * level.at("coverage").get<double>());
        c.wrongCode.push_back(100 * level.at("wrong_code_share").get<double>());
        c.wrongDecode.push_back(100 * level.at("wrong_decode_share").get<double>());
        c.coarse.push_back(100 * level.at("coarse_share").get<double>());
        c.depth.push_back(level.at("depth_rms_mm").get<double>());
    }
    const std::filesystem::path out = argv[3];
    std::filesystem::create_directories(out);
    vpe::plot::SvgLinePlot coverage("What a noisy camera decodes (simulated small room)",
                                    "log10 full well (electrons)", "% of lit camera pixels");
    vpe::plot::SvgLinePlot wrong("What a noisy camera decodes wrong", "log10 full well (electrons)",
                                 "% of decoded pixels");
    vpe::plot::SvgLinePlot depth("What a noisy camera costs in depth",
                                 "log10 full well (electrons)", "depth RMS (mm)");
    for (const auto& [name, c] : curves) {
        const std::string dash = name == "gamma8" ? "6 3" : "";
        coverage.addSeries(name, c.fullWell, c.coverage, dash);
        wrong.addSeries(name + " > 1 px", c.fullWell, c.wrongDecode, dash);
        wrong.addSeries(name + " Gray bin", c.fullWell, c.coarse, name == "gamma8" ? "1 2" : "3 1");
        wrong.addSeries(name + " beyond σ", c.fullWell, c.wrongCode,
                        name == "gamma8" ? "2 3" : "8 2 2 2");
        depth.addSeries(name, c.fullWell, c.depth, dash);
    }
    coverage.write(out / "noise-coverage.svg");
    wrong.write(out / "noise-wrong.svg");
    depth.write(out / "noise-depth.svg");
    std::printf("wrote %s/noise-coverage.svg, noise-wrong.svg and noise-depth.svg\n", out.c_str());
    return 0;
}
