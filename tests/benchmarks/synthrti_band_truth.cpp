// SPDX-License-Identifier: MIT
// Writes derived ground-truth material labels for SynthRTI's Multi sets (SynthRTI ships none)
// as 8-bit label images for `vpe segment --truth`: OUT/Object<o>/material<m>.png.
//   vpe_synthrti_band_truth MULTI_DIR --out-dir OUT [--json]
// Which bands are one material (the layout) is decided on Object1, whose surface is nearly
// flat so edges between bands are clean, and used for Object2's set of the same name (the
// same nine textures); each set's band lines are then located in its own images.
#include "support/synthrti_band_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/image/image_file.h"

#include "tool_errors.h"

namespace {

using namespace vpe::testing;

std::vector<std::string> materialSets(const std::filesystem::path& object) {
    std::vector<std::string> names;
    for (int m = 1; std::filesystem::is_directory(object / ("material" + std::to_string(m))); ++m) {
        names.push_back("material" + std::to_string(m));
    }
    if (names.empty()) {
        throw vpe::common::InputError(object, "no material1/ folder");
    }
    return names;
}

std::vector<double> positions(const std::vector<BandLine>& lines) {
    std::vector<double> values;
    for (const BandLine& line : lines) {
        values.push_back(line.position);
    }
    return values;
}

double pieceSpread(const BandGrid& grid) {
    double spread = 0;
    for (const std::vector<BandLine>* lines : {&grid.columnLines, &grid.rowLines}) {
        for (const BandLine& line : *lines) {
            for (double piece : line.pieces) {
                spread = std::max(spread, std::fabs(piece - line.position));
            }
        }
    }
    return spread;
}

// The layouts, the truth label images in OUT and (with `json`) the report on stdout.
void writeBandTruth(const std::filesystem::path& multi, const std::filesystem::path& outDir,
                    bool json) {
    const std::vector<std::string> sets = materialSets(multi / "Object1");
    // 1. The layouts, on Object1's finest grid located from all its sets at once.
    std::vector<std::filesystem::path> reference;
    for (const std::string& set : sets) {
        reference.push_back(multi / "Object1" / set / "Dome");
    }
    const BandGridOptions fine;
    const BandGrid fineGrid = locateBandGrid(reference, fine);
    const BandMergeOptions merge;
    nlohmann::json report;
    report["boundary_levels"] = merge.boundaryLevels;
    report["fine_grid"] = {{"column_lines", positions(fineGrid.columnLines)},
                           {"row_lines", positions(fineGrid.rowLines)},
                           {"piece_spread", pieceSpread(fineGrid)}};
    std::vector<BandTruth> layouts;
    for (std::size_t s = 0; s < sets.size(); ++s) {
        const LineContrasts contrasts = measureLineContrasts(reference[s], fineGrid, merge);
        layouts.push_back(labelBands(fineGrid, contrasts, merge.boundaryLevels));
        // The closest decisions either way show how clear the threshold is.
        double highestDropped = 0, lowestBoundary = 1e9;
        for (const std::vector<double>* lines : {&contrasts.columnLines, &contrasts.rowLines}) {
            for (double contrast : *lines) {
                if (contrast < merge.boundaryLevels) {
                    highestDropped = std::max(highestDropped, contrast);
                } else {
                    lowestBoundary = std::min(lowestBoundary, contrast);
                }
            }
        }
        std::fprintf(stderr,
                     "%s: %d columns x %d rows = %d materials (lines dropped up to %.0f "
                     "levels, boundaries from %.0f)\n",
                     sets[s].c_str(), layouts.back().materialColumns, layouts.back().materialRows,
                     layouts.back().materials, highestDropped, lowestBoundary);
        report["layouts"][sets[s]] = {{"columns", layouts.back().materialColumns},
                                      {"rows", layouts.back().materialRows},
                                      {"materials", layouts.back().materials},
                                      {"column_line_contrasts", contrasts.columnLines},
                                      {"row_line_contrasts", contrasts.rowLines},
                                      {"highest_dropped", highestDropped},
                                      {"lowest_boundary", lowestBoundary}};
    }
    // 2. Each set's lines for its layout. The sets of one object with as many bands in a
    // direction share those lines (checked: within 4 px on Object2), so the lines are
    // located on all of them at once, which outvotes the relief's edges.
    for (const char* object : {"Object1", "Object2"}) {
        auto pooled = [&](bool columns, int bands) {
            std::vector<std::filesystem::path> captures;
            for (std::size_t s = 0; s < sets.size(); ++s) {
                if ((columns ? layouts[s].materialColumns : layouts[s].materialRows) == bands) {
                    captures.push_back(multi / object / sets[s] / "Dome");
                }
            }
            BandGridOptions options;
            options.columns = columns ? bands : 1;
            options.rows = columns ? 1 : bands;
            const BandGrid grid = locateBandGrid(captures, options);
            return columns ? grid.columnLines : grid.rowLines;
        };
        for (std::size_t s = 0; s < sets.size(); ++s) {
            const std::filesystem::path capture = multi / object / sets[s] / "Dome";
            BandGrid grid;
            grid.width = fineGrid.width;
            grid.height = fineGrid.height;
            grid.pieceLength = fine.pieceLength;
            grid.columnLines = pooled(true, layouts[s].materialColumns);
            grid.rowLines = pooled(false, layouts[s].materialRows);
            // Every line of this grid is a boundary: keep them all.
            LineContrasts all;
            all.columnLines.assign(grid.columnLines.size(), 1.0);
            all.rowLines.assign(grid.rowLines.size(), 1.0);
            const BandTruth truth = labelBands(grid, all, 0.5);
            const std::filesystem::path out = outDir / object / (sets[s] + ".png");
            vpe::image::writeImage8(out, grid.width, grid.height, 1, truth.labels);
            std::fprintf(stderr, "%s/%s: %d materials, column lines", object, sets[s].c_str(),
                         truth.materials);
            for (double position : positions(grid.columnLines)) {
                std::fprintf(stderr, " %.0f", position);
            }
            std::fprintf(stderr, ", row lines");
            for (double position : positions(grid.rowLines)) {
                std::fprintf(stderr, " %.0f", position);
            }
            std::fprintf(stderr, "; pieces within %.0f px\n", pieceSpread(grid));
            report["sets"][std::string(object) + "/" + sets[s]] = {
                {"materials", truth.materials},
                {"labels", out.string()},
                {"column_lines", positions(grid.columnLines)},
                {"row_lines", positions(grid.rowLines)},
                {"piece_spread", pieceSpread(grid)}};
        }
    }
    if (json) {
        std::printf("%s\n", report.dump().c_str());
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::filesystem::path multi, outDir;
    bool json = false;
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        if (argument == "--out-dir" && i + 1 < argc) {
            outDir = argv[++i];
        } else if (argument == "--json") {
            json = true;
        } else if (multi.empty() && !argument.starts_with("--")) {
            multi = argument;
        } else {
            multi.clear();
            break;
        }
    }
    if (multi.empty() || outDir.empty()) {
        std::fprintf(stderr, "usage: %s MULTI_DIR --out-dir OUT [--json]\n", argv[0]);
        return 2;
    }
    return vpe::benchmarks::exitStatusOf([&] { writeBandTruth(multi, outDir, json); });
}
