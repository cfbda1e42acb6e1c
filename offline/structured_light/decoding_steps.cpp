// SPDX-License-Identifier: MIT
// The decoders' shared steps: the noise fit, the mixed pixels, the tally.
#include "decoding_steps.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/quantile.h"

namespace vpe::structured_light::detail {

namespace {

// Codes the declared projector does not have (a bin starting at or beyond its width or height)
// on more than this share of an axis' certain codes: the patterns were made for another size or
// step than the manifest says. A right declaration leaves them to misread bits: none of the
// 3.2 million certain codes per axis of the procam-calibration sample's five poses declared
// 1024x768; declared 1920x1080 step 2, 31 % of capture_0's row codes are 540..767.
constexpr double kWrongSizeShare = 0.02;

}  // namespace

void checkCodesFitTheProjector(const ScanCapture& capture, const AxisCode& columns,
                               const AxisCode& rows, const std::vector<DecodeStatus>& status) {
    const AxisCode* axes[2] = {&columns, &rows};
    const proto::StructuredLightParameters& parameters = capture.sequence().parameters();
    const int binWidth = capture.sequence().grayBinWidth();
    const int extents[2] = {parameters.width, parameters.height};
    std::string problems;
    for (int a = 0; a < 2; ++a) {
        const AxisCode& axis = *axes[a];
        // Bins 0 .. bins − 1 exist; the last may be cut short by the projector's edge.
        const std::uint32_t bins =
            static_cast<std::uint32_t>((extents[a] + binWidth - 1) / binWidth);
        std::size_t certain = 0, beyond = 0;
        std::uint32_t highest = 0;
        for (std::size_t q = 0; q < status.size(); ++q) {
            if (status[q] == DecodeStatus::kDark || axis.uncertain[q] != kNoUncertainBit) {
                continue;
            }
            ++certain;
            const std::uint32_t bin = proto::grayDecode(axis.code[q]);
            if (bin >= bins) {
                ++beyond;
                highest = std::max(highest, bin);
            }
        }
        if (certain == 0 || double(beyond) <= kWrongSizeShare * double(certain)) {
            continue;
        }
        const char* name = a == 0 ? "column" : "row";
        problems += std::string(problems.empty() ? "" : "; ") +
                    std::to_string(
                        static_cast<int>(std::lround(100.0 * double(beyond) / double(certain)))) +
                    "% of the decoded " + name + " codes are " + std::to_string(bins) + ".." +
                    std::to_string(highest) + ", beyond the " + std::to_string(bins) + " " + name +
                    " codes (0.." + std::to_string(bins - 1) + ") a " +
                    std::to_string(parameters.width) + "x" + std::to_string(parameters.height) +
                    " projector with step " + std::to_string(parameters.codeStep) + " has";
    }
    if (!problems.empty()) {
        throw common::InputError(capture.folder() / proto::kScanManifestName,
                                 problems +
                                     ": is the projector's size right (vpe import-graycode "
                                     "--projector, --step)?");
    }
}

NoiseModel fitNoiseModel(const std::vector<double>& level, const std::vector<double>& residual,
                         double quantum) {
    NoiseModel model;
    // Four images, two at each of two levels whose sum is x: var(r) = 4a + 2b·x (for
    // p + i − W − B, 2σ²(W) + 2σ²(B) = 4a + 2b·(W + B)). A line through the binned variances
    // (robust: MAD per bin).
    constexpr int kBins = 16;
    std::vector<std::vector<double>> bins(kBins);
    std::vector<std::vector<double>> levels(kBins);
    for (std::size_t k = 0; k < level.size(); ++k) {
        const int bin = std::clamp(static_cast<int>(level[k] / 2 * kBins), 0, kBins - 1);
        bins[static_cast<std::size_t>(bin)].push_back(residual[k]);
        levels[static_cast<std::size_t>(bin)].push_back(level[k]);
    }
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (int b = 0; b < kBins; ++b) {
        auto& values = bins[static_cast<std::size_t>(b)];
        if (values.size() < 64) {
            continue;
        }
        const double centre = common::quantile(values, 0.5);
        for (double& v : values) {
            v = std::abs(v - centre);
        }
        const double sigma = 1.4826 * common::quantile(values, 0.5);
        const double x = common::quantile(levels[static_cast<std::size_t>(b)], 0.5);
        const double y = sigma * sigma;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        n += 1;
    }
    double slope = 0, intercept = n > 0 ? sy / n : 0;
    if (n >= 2 && sxx * n - sx * sx > 1e-12) {
        slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        intercept = (sy - slope * sx) / n;
    }
    slope = std::max(slope, 0.0);
    // A capture without measurable noise still has its quantization's.
    model.constant = std::max(intercept / 4, quantum * quantum / 12);
    model.perSignal = slope / 2;
    return model;
}

double fitCameraGamma(const std::vector<float>& white, const std::vector<float>& black,
                      const std::vector<float>& on, const std::vector<float>& off) {
    // The pixels both images of the pair light partly, well inside the camera's range: chosen
    // by p − i, whose noise is independent of the p + i the fit reads (equal variances), so
    // that the choice does not bias the sum.
    std::vector<std::size_t> partial;
    for (std::size_t q = 0; q < white.size(); ++q) {
        const double w = white[q], b = black[q], range = w - b;
        if (range > 0.25 && w < 0.98 && std::abs(double(on[q]) - double(off[q])) < 0.4 * range) {
            partial.push_back(q);
        }
    }
    constexpr std::size_t kFewest = 256, kEnough = 20000;
    if (partial.size() < kFewest) {
        return 1;
    }
    if (partial.size() > kEnough) {  // an even sample: the median needs no more
        const std::size_t stride = partial.size() / kEnough + 1;
        for (std::size_t k = 0; k * stride < partial.size(); ++k) {
            partial[k] = partial[k * stride];
        }
        partial.resize((partial.size() + stride - 1) / stride);
    }
    // The median of (p^γ + i^γ − w^γ − b^γ) / (w^γ − b^γ) falls as γ grows (the curve's bend
    // is undone): its zero, by bisection.
    std::vector<double> residual(partial.size());
    const auto medianResidual = [&](double gamma) {
        for (std::size_t k = 0; k < partial.size(); ++k) {
            const std::size_t q = partial[k];
            const double w = std::pow(double(white[q]), gamma),
                         b = std::pow(double(black[q]), gamma);
            residual[k] =
                (std::pow(double(on[q]), gamma) + std::pow(double(off[q]), gamma) - w - b) /
                (w - b);
        }
        return common::quantile(residual, 0.5);
    };
    double low = 0.5, high = 4.0;
    if (medianResidual(low) <= 0 || medianResidual(high) >= 0) {
        return 1;  // no γ in range explains it: leave the values as they are
    }
    for (int iteration = 0; iteration < 30; ++iteration) {
        const double middle = 0.5 * (low + high);
        (medianResidual(middle) > 0 ? low : high) = middle;
    }
    const double gamma = 0.5 * (low + high);
    return std::abs(gamma - 1) < 0.05 ? 1.0 : gamma;
}

void linearize(std::vector<float>& values, double gamma) {
    if (gamma == 1) {
        return;
    }
    for (float& v : values) {
        v = static_cast<float>(std::pow(std::clamp(double(v), 0.0, 1.0), gamma));
    }
}

void markMixedPixels(DecodedScan& scan, double maxBend, double grayBinWidth, unsigned threads) {
    const std::size_t pixels = scan.status.size();
    // Mixed pixels across a jump: along a row or a column the decoded coordinates bend one way
    // at a pixel and the other way at its neighbour — a step, which a smooth surface, even seen
    // at a grazing angle (bends of one sign), does not make.
    const int w = scan.width, h = scan.height;
    const auto decodedAt = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < w && y < h &&
               scan.status[static_cast<std::size_t>(y) * w + x] == DecodeStatus::kDecoded;
    };
    const auto byGrayBin = [&](int x, int y) {
        return scan.source[static_cast<std::size_t>(y) * w + x] == PositionSource::kGrayBin;
    };
    // The bend of `map` at (x, y) along (dx, dy) beyond what the pixels' rounding allows (its
    // sign kept); NaN without both neighbours.
    const auto bend = [&](const std::vector<float>& map, int x, int y, int dx, int dy) {
        if (!decodedAt(x, y) || !decodedAt(x - dx, y - dy) || !decodedAt(x + dx, y + dy)) {
            return std::numeric_limits<double>::quiet_NaN();
        }
        const auto at = [&](int u, int v) {
            return double(map[static_cast<std::size_t>(v) * w + u]);
        };
        const double value = at(x - dx, y - dy) + at(x + dx, y + dy) - 2 * at(x, y);
        const bool rounded =
            byGrayBin(x, y) || byGrayBin(x - dx, y - dy) || byGrayBin(x + dx, y + dy);
        const double allowed = rounded ? 2 * grayBinWidth : 0.0;
        return std::copysign(std::max(0.0, std::abs(value) - allowed), value);
    };
    std::vector<std::uint8_t> edge(pixels, 0);
    common::parallelFor(
        static_cast<std::size_t>(h), 16, threads, [&](std::size_t begin, std::size_t end) {
            for (int y = static_cast<int>(begin); y < static_cast<int>(end); ++y) {
                for (int x = 0; x < w; ++x) {
                    if (!decodedAt(x, y)) {
                        continue;
                    }
                    bool step = false;
                    for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                        for (const std::vector<float>* map : {&scan.projectorX, &scan.projectorY}) {
                            const double here = bend(*map, x, y, dx, dy);
                            for (const int side : {-1, 1}) {
                                const double there =
                                    bend(*map, x + side * dx, y + side * dy, dx, dy);
                                step = step || (std::abs(here) > maxBend &&
                                                std::abs(there) > maxBend && here * there < 0);
                            }
                        }
                    }
                    edge[static_cast<std::size_t>(y) * w + x] = step ? 1 : 0;
                }
            }
        });
    for (std::size_t q = 0; q < pixels; ++q) {
        if (edge[q]) {
            scan.status[q] = DecodeStatus::kEdge;
            scan.projectorX[q] = scan.projectorY[q] = scan.precision[q] = kNaN;
            scan.source[q] = PositionSource::kNone;
        }
    }
}

void countStatuses(DecodedScan& scan, std::size_t lit) {
    scan.statusCounts.assign(kDecodeStatusCount, 0);
    for (const DecodeStatus status : scan.status) {
        ++scan.statusCounts[static_cast<std::size_t>(status)];
    }
    scan.decoded = scan.statusCounts[0];
    scan.sourceCounts.assign(kPositionSourceCount, 0);
    for (const PositionSource source : scan.source) {
        ++scan.sourceCounts[static_cast<std::size_t>(source)];
    }
    scan.lit = lit;
}

}  // namespace vpe::structured_light::detail
