// SPDX-License-Identifier: MIT
// SvgLinePlot: a small, dependency-free line chart (axes, ticks, legend, dash styles) for
// the figures vpe writes, e.g. the Fig. 6 sweep. SVG opens in any browser and diffs as text.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vpe::plot {

class SvgLinePlot {
public:
    SvgLinePlot(std::string title, std::string xLabel, std::string yLabel);

    // dash: an SVG stroke-dasharray ("" for solid).
    void addSeries(std::string name, std::vector<double> x, std::vector<double> y,
                   std::string dash = "");
    // Values above the cap are drawn at the top edge (keeps one blown-up curve from
    // flattening the rest); 0 means no cap.
    void setYCap(double cap) { yCap_ = cap; }

    std::string render() const;
    void write(const std::filesystem::path& path) const;

private:
    struct Series {
        std::string name;
        std::vector<double> x, y;
        std::string dash;
    };
    std::string title_, xLabel_, yLabel_;
    std::vector<Series> series_;
    double yCap_ = 0;
};

// Round tick positions covering [low, high].
std::vector<double> niceTicks(double low, double high, int approximateCount);

}  // namespace vpe::plot
