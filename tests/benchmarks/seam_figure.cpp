// SPDX-License-Identifier: MIT
// vpe_seam_figure TILED_QUILT PLAIN_QUILT --out DIR [--bundles TILED.vpeb PLAIN.vpeb]
//
// The numbers and plots of scripts/seam-figure.sh: for every region of two `vpe quilt` folders
// of one model — quilted with --wrap on and with --wrap off — the step from the last column to
// the first (u = 1 | 0) against the interior neighbour-column steps, drawn as the sorted
// interior steps with the seam's step across them (DIR/seam-steps-region<k>.svg); and, given the
// two bundles baked from them, the same on a rendered frame (testing::measureFrameSeam: pixel
// pairs across the seam against pairs beside it). The last stdout line is one JSON object.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/plot/svg_line_plot.h"
#include "vpe/proto/bundle.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/quilt/seam_statistics.h"

#include "support/frame_seam.h"

namespace {

vpe::quilt::SeamStatistics regionSeam(const std::filesystem::path& map) {
    vpe::model::ModelReader reader(map);
    const vpe::model::ModelInfo info = reader.info();
    vpe::model::ModelRows rows;
    reader.readRows(0, info.height, rows);
    return vpe::quilt::measureSeam(rows.coefficient, info.width, info.height,
                                   3 * rows.coefficients);
}

// The interior column steps sorted, over their share (a quantile curve at 101 points), in
// units of their mean.
void addSorted(vpe::plot::SvgLinePlot& plot, const std::string& name,
               const vpe::quilt::SeamStatistics& s, const std::string& dash) {
    std::vector<double> steps = s.columnSteps;
    std::sort(steps.begin(), steps.end());
    std::vector<double> x, y;
    for (int i = 0; i <= 100; ++i) {
        const auto at = static_cast<std::size_t>(
            std::lround(i / 100.0 * static_cast<double>(steps.size() - 1)));
        x.push_back(i / 100.0);
        y.push_back(steps[at] / s.interiorMean);
    }
    plot.addSeries(name, std::move(x), std::move(y), dash);
}

int run(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    std::filesystem::path tiled, plain, out, tiledBundle, plainBundle;
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--out" && i + 1 < args.size()) {
            out = args[++i];
        } else if (args[i] == "--bundles" && i + 2 < args.size()) {
            tiledBundle = args[++i];
            plainBundle = args[++i];
        } else if (tiled.empty()) {
            tiled = args[i];
        } else if (plain.empty()) {
            plain = args[i];
        } else {
            throw vpe::common::InputError("unexpected argument '" + args[i] + "'");
        }
    }
    if (tiled.empty() || plain.empty() || out.empty()) {
        std::fprintf(stderr,
                     "usage: vpe_seam_figure TILED_QUILT PLAIN_QUILT --out DIR "
                     "[--bundles TILED.vpeb PLAIN.vpeb]\n");
        return 2;
    }
    std::filesystem::create_directories(out);
    nlohmann::json report;
    report["regions"] = nlohmann::json::array();
    const std::vector<std::filesystem::path> tiledMaps = vpe::quilt::listRegionMaps(tiled);
    const std::vector<std::filesystem::path> plainMaps = vpe::quilt::listRegionMaps(plain);
    for (std::size_t r = 0; r < tiledMaps.size() && r < plainMaps.size(); ++r) {
        const vpe::quilt::SeamStatistics on = regionSeam(tiledMaps[r]);
        const vpe::quilt::SeamStatistics off = regionSeam(plainMaps[r]);
        vpe::plot::SvgLinePlot plot(
            "Region " + std::to_string(r) + ": the u seam against interior neighbours",
            "interior neighbour-column pairs, sorted by their step (share)",
            "mean step over the rows / interior mean");
        addSorted(plot, "interior, tiled quilt", on, "");
        addSorted(plot, "interior, plain quilt", off, "2,3");
        plot.addSeries("seam, tiled quilt", {0.0, 1.0}, {on.ratio(), on.ratio()}, "8,4");
        plot.addSeries("seam, plain quilt", {0.0, 1.0}, {off.ratio(), off.ratio()}, "1,4");
        const std::filesystem::path svg = out / ("seam-steps-region" + std::to_string(r) + ".svg");
        plot.write(svg);
        std::printf(
            "region %zu: seam step / interior mean: tiled %.2f (rank %.2f), plain %.2f "
            "(rank %.2f); interior p95 / mean %.2f, max / mean %.2f: %s\n",
            r, on.ratio(), on.seamRank, off.ratio(), off.seamRank, on.interiorP95 / on.interiorMean,
            on.interiorMax / on.interiorMean, svg.c_str());
        report["regions"].push_back(
            {{"tiled", vpe::quilt::seamJson(on)}, {"plain", vpe::quilt::seamJson(off)}});
    }
    if (!tiledBundle.empty()) {
        using Steps = vpe::testing::FrameSeamSteps;
        for (const auto& [name, path] :
             {std::pair{"tiled", tiledBundle}, std::pair{"plain", plainBundle}}) {
            const vpe::proto::BundleFile file = vpe::proto::BundleFile::open(path);
            // A light on the viewer's side (the bundle's), to the right and above.
            const double side = file->settings().viewerPosition[2] < 0 ? -1.0 : 1.0;
            const vpe::proto::Vec3d light{0.3 * side, 0.35, 0.6 * side};
            const Steps steps = vpe::testing::measureFrameSeam(file.view(), light, 0.03);
            std::printf(
                "frame (%s): %zu pixel pairs across the seam, mean step %.4g; %zu beside "
                "it, mean %.4g, p95 %.4g; ratio %.2f\n",
                name, steps.seam.size(), Steps::mean(steps.seam), steps.interior.size(),
                Steps::mean(steps.interior), Steps::quantile(steps.interior, 0.95), steps.ratio());
            report["frame"][name] = {{"seam_pairs", steps.seam.size()},
                                     {"seam_mean", Steps::mean(steps.seam)},
                                     {"interior_pairs", steps.interior.size()},
                                     {"interior_mean", Steps::mean(steps.interior)},
                                     {"interior_p95", Steps::quantile(steps.interior, 0.95)},
                                     {"ratio", steps.ratio()}};
        }
    }
    std::cout << report.dump() << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_seam_figure: %s\n", error.what());
        return 2;
    }
}
