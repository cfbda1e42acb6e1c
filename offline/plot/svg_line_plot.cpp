// SPDX-License-Identifier: MIT
// SVG line chart.
#include "vpe/plot/svg_line_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "vpe/proto/atomic_file.h"

namespace vpe::plot {

namespace {

constexpr double kWidth = 720, kHeight = 480;
constexpr double kLeft = 70, kRight = 170, kTop = 40, kBottom = 60;
const char* const kColours[] = {"#1b1b1b", "#c0392b", "#2471a3", "#239b56",
                                "#b9770e", "#7d3c98", "#117a65", "#884ea0"};

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '&':
                out += "&amp;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

}  // namespace

std::vector<double> niceTicks(double low, double high, int approximateCount) {
    if (!(high > low)) {
        return {low};
    }
    const double raw = (high - low) / std::max(approximateCount, 1);
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    double step = magnitude;
    for (double factor : {1.0, 2.0, 2.5, 5.0, 10.0}) {
        step = factor * magnitude;
        if (step >= raw) {
            break;
        }
    }
    std::vector<double> ticks;
    for (double t = std::ceil(low / step - 1e-9) * step; t <= high + step * 1e-9; t += step) {
        ticks.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
    }
    return ticks;
}

SvgLinePlot::SvgLinePlot(std::string title, std::string xLabel, std::string yLabel)
    : title_(std::move(title)), xLabel_(std::move(xLabel)), yLabel_(std::move(yLabel)) {}

void SvgLinePlot::addSeries(std::string name, std::vector<double> x, std::vector<double> y,
                            std::string dash) {
    series_.push_back({std::move(name), std::move(x), std::move(y), std::move(dash)});
}

std::string SvgLinePlot::render() const {
    double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin;
    double yMin = xMin, yMax = -xMin;
    for (const Series& s : series_) {
        for (std::size_t i = 0; i < s.x.size(); ++i) {
            if (!std::isfinite(s.y[i])) {
                continue;
            }
            xMin = std::min(xMin, s.x[i]);
            xMax = std::max(xMax, s.x[i]);
            const double y = yCap_ > 0 ? std::min(s.y[i], yCap_) : s.y[i];
            yMin = std::min(yMin, y);
            yMax = std::max(yMax, y);
        }
    }
    if (!std::isfinite(xMin)) {
        xMin = 0, xMax = 1, yMin = 0, yMax = 1;
    }
    // The axis spans the data (plus a margin), not zero: differences between curves are
    // what these plots are for.
    const double margin = std::max(0.05 * (yMax - yMin), 1e-9);
    const std::vector<double> xTicks = niceTicks(xMin, xMax, 8);
    const std::vector<double> yTicks = niceTicks(yMin - margin, yMax + margin, 6);
    xMin = std::min(xMin, xTicks.front());
    xMax = std::max(xMax, xTicks.back());
    yMin = std::min(yMin - margin, yTicks.front());
    yMax = std::max(yMax + margin, yTicks.back());
    const double plotWidth = kWidth - kLeft - kRight;
    const double plotHeight = kHeight - kTop - kBottom;
    auto px = [&](double x) { return kLeft + (x - xMin) / (xMax - xMin) * plotWidth; };
    auto py = [&](double y) { return kTop + (1 - (y - yMin) / (yMax - yMin)) * plotHeight; };

    std::ostringstream svg;
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\""
        << kHeight << "\" font-family=\"sans-serif\" font-size=\"13\">\n"
        << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        << "<text x=\"" << kLeft + plotWidth / 2 << "\" y=\"24\" text-anchor=\"middle\" "
        << "font-size=\"15\">" << escape(title_) << "</text>\n";
    for (double t : xTicks) {
        svg << "<line x1=\"" << px(t) << "\" y1=\"" << kTop << "\" x2=\"" << px(t) << "\" y2=\""
            << kTop + plotHeight << "\" stroke=\"#e5e5e5\"/>\n"
            << "<text x=\"" << px(t) << "\" y=\"" << kTop + plotHeight + 18
            << "\" text-anchor=\"middle\">" << number(t) << "</text>\n";
    }
    for (double t : yTicks) {
        svg << "<line x1=\"" << kLeft << "\" y1=\"" << py(t) << "\" x2=\"" << kLeft + plotWidth
            << "\" y2=\"" << py(t) << "\" stroke=\"#e5e5e5\"/>\n"
            << "<text x=\"" << kLeft - 8 << "\" y=\"" << py(t) + 4 << "\" text-anchor=\"end\">"
            << number(t) << "</text>\n";
    }
    svg << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << plotWidth
        << "\" height=\"" << plotHeight << "\" fill=\"none\" stroke=\"#333\"/>\n"
        << "<text x=\"" << kLeft + plotWidth / 2 << "\" y=\"" << kHeight - 18
        << "\" text-anchor=\"middle\">" << escape(xLabel_) << "</text>\n"
        << "<text transform=\"translate(18," << kTop + plotHeight / 2
        << ") rotate(-90)\" text-anchor=\"middle\">" << escape(yLabel_) << "</text>\n";
    for (std::size_t i = 0; i < series_.size(); ++i) {
        const Series& s = series_[i];
        const char* colour = kColours[i % (sizeof kColours / sizeof kColours[0])];
        svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\"";
        if (!s.dash.empty()) {
            svg << " stroke-dasharray=\"" << s.dash << "\"";
        }
        svg << " points=\"";
        for (std::size_t j = 0; j < s.x.size(); ++j) {
            if (std::isfinite(s.y[j])) {
                const double y = yCap_ > 0 ? std::min(s.y[j], yCap_) : s.y[j];
                svg << px(s.x[j]) << "," << py(y) << " ";
            }
        }
        svg << "\"/>\n";
        for (std::size_t j = 0; j < s.x.size(); ++j) {
            if (std::isfinite(s.y[j])) {
                const double y = yCap_ > 0 ? std::min(s.y[j], yCap_) : s.y[j];
                svg << "<circle cx=\"" << px(s.x[j]) << "\" cy=\"" << py(y)
                    << "\" r=\"2.5\" fill=\"" << colour << "\"/>\n";
            }
        }
        const double legendY = kTop + 14 + 22 * static_cast<double>(i);
        svg << "<line x1=\"" << kWidth - kRight + 14 << "\" y1=\"" << legendY << "\" x2=\""
            << kWidth - kRight + 50 << "\" y2=\"" << legendY << "\" stroke=\"" << colour
            << "\" stroke-width=\"2\""
            << (s.dash.empty() ? "" : " stroke-dasharray=\"" + s.dash + "\"") << "/>\n<text x=\""
            << kWidth - kRight + 56 << "\" y=\"" << legendY + 4 << "\">" << escape(s.name)
            << "</text>\n";
    }
    svg << "</svg>\n";
    return svg.str();
}

void SvgLinePlot::write(const std::filesystem::path& path) const {
    proto::writeTextFileAtomically(path, render());
}

}  // namespace vpe::plot
