// SPDX-License-Identifier: MIT
// splitFloor: a robust linear fit of the floor per channel, its errors by a block bootstrap.
#include "vpe/radiometry/floor_split.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unordered_map>

#include <Eigen/Dense>

#include "vpe/common/quantile.h"

namespace vpe::radiometry {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Huber's weights past this many robust σ: a pixel the model does not describe (an edge whose
// correspondence is off, a speck of dust) pulls the fit no more than a few noisy ones.
constexpr double kHuber = 2.5;
constexpr std::size_t kMinPixels = 16;

// SplitMix64: a small deterministic generator for the resampling.
struct SplitMix {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t x = (state += 0x9E3779B97F4A7C15ull);
        x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
        x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
        return x ^ (x >> 31);
    }
};

// Half the width of the central 68 % of a sample: σ for a normal one, and not thrown by the few
// resamples a near-singular fit sends far away.
double spreadOf(std::vector<double> values) {
    const double high = common::quantile(values, 0.8413);
    const double low = common::quantile(std::move(values), 0.1587);
    return 0.5 * (high - low);
}

struct ChannelResult {
    double black = kNaN, blackSigma = kNaN;
    double projectorBlack = kNaN, projectorBlackSigma = kNaN;
    double ambient = kNaN, ambientSigma = kNaN;
    double floor = kNaN, ambientAtMost = kNaN, leverage = kNaN;
    std::size_t pixels = 0, blocks = 0;
};

// y = D − (the known black); the columns: [1,] F, F / S. knownBlack NaN: fitted.
ChannelResult splitChannel(const std::vector<FloorSample>& samples, double knownBlack,
                           const FloorSplitOptions& options, std::uint64_t seed) {
    const bool fitBlack = std::isnan(knownBlack);
    std::vector<const FloorSample*> used;
    for (const FloorSample& s : samples) {
        if (std::isfinite(s.floor) && s.irradiance > 0 && s.geometry > 0) {
            used.push_back(&s);
        }
    }
    ChannelResult r;
    r.pixels = used.size();
    if (used.size() < kMinPixels) {
        return r;  // nothing to fit: every part NaN, and the split not trusted
    }
    const int terms = fitBlack ? 3 : 2;
    const Eigen::Index n = static_cast<Eigen::Index>(used.size());
    Eigen::MatrixXd x(n, terms);
    Eigen::VectorXd y(n);
    const double offset = fitBlack ? 0.0 : knownBlack;
    std::vector<double> floors, bounds;
    floors.reserve(used.size());
    bounds.reserve(used.size());
    for (Eigen::Index i = 0; i < n; ++i) {
        const FloorSample& s = *used[static_cast<std::size_t>(i)];
        const double f = s.irradiance, albedo = double(s.irradiance) / double(s.geometry);
        int column = 0;
        if (fitBlack) {
            x(i, column++) = 1;
        }
        x(i, column++) = f;
        x(i, column) = albedo;
        y(i) = double(s.floor) - offset;
        floors.push_back(s.floor);
        bounds.push_back(y(i) / albedo);
    }
    r.floor = common::quantile(std::move(floors), 0.5);
    r.ambientAtMost = common::quantile(std::move(bounds), 0.5);

    // Iteratively reweighted least squares with Huber's weights.
    Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(terms);
    for (int iteration = 0; iteration < 6; ++iteration) {
        const Eigen::MatrixXd normal = x.transpose() * w.asDiagonal() * x;
        theta = normal.ldlt().solve(x.transpose() * w.asDiagonal() * y);
        const Eigen::VectorXd residual = y - x * theta;
        std::vector<double> magnitudes(residual.size());
        for (Eigen::Index i = 0; i < n; ++i) {
            magnitudes[static_cast<std::size_t>(i)] = std::abs(residual(i));
        }
        const double sigma = 1.4826 * common::quantile(std::move(magnitudes), 0.5);
        if (!(sigma > 0)) {
            break;
        }
        for (Eigen::Index i = 0; i < n; ++i) {
            const double a = std::abs(residual(i)) / sigma;
            w(i) = a > kHuber ? kHuber / a : 1.0;
        }
    }

    // The albedo's spread that the other terms do not follow (its part orthogonal to them, in the
    // fit's weights), as a share of its mean: the leverage the room's light has.
    {
        const Eigen::MatrixXd others = x.leftCols(terms - 1);
        const Eigen::VectorXd albedo = x.col(terms - 1);
        const Eigen::VectorXd fit = (others.transpose() * w.asDiagonal() * others)
                                        .ldlt()
                                        .solve(others.transpose() * w.asDiagonal() * albedo);
        const Eigen::VectorXd orthogonal = albedo - others * fit;
        const double weights = w.sum();
        r.leverage = std::sqrt(orthogonal.cwiseProduct(orthogonal).dot(w) / weights) /
                     (albedo.dot(w) / weights);
    }

    // Each block's weighted moments, then the fit over resampled blocks.
    std::unordered_map<std::uint32_t, std::size_t> blockIndex;
    std::vector<Eigen::MatrixXd> moments;
    std::vector<Eigen::VectorXd> targets;
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto [at, fresh] =
            blockIndex.try_emplace(used[static_cast<std::size_t>(i)]->block, moments.size());
        if (fresh) {
            moments.push_back(Eigen::MatrixXd::Zero(terms, terms));
            targets.push_back(Eigen::VectorXd::Zero(terms));
        }
        const Eigen::VectorXd row = x.row(i).transpose();
        moments[at->second] += w(i) * row * row.transpose();
        targets[at->second] += w(i) * y(i) * row;
    }
    r.blocks = moments.size();
    std::array<std::vector<double>, 3> resampled;
    SplitMix random{seed};
    for (int b = 0; b < options.bootstrap; ++b) {
        Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(terms, terms);
        Eigen::VectorXd target = Eigen::VectorXd::Zero(terms);
        for (std::size_t k = 0; k < moments.size(); ++k) {
            const std::size_t pick = random.next() % moments.size();
            normal += moments[pick];
            target += targets[pick];
        }
        const Eigen::VectorXd t = normal.ldlt().solve(target);
        for (int j = 0; j < terms; ++j) {
            resampled[static_cast<std::size_t>(j)].push_back(t(j));
        }
    }
    int column = 0;
    if (fitBlack) {
        r.black = theta(column);
        r.blackSigma = spreadOf(resampled[static_cast<std::size_t>(column++)]);
    } else {
        r.black = knownBlack;
        r.blackSigma = 0;
    }
    r.projectorBlack = theta(column);
    r.projectorBlackSigma = spreadOf(resampled[static_cast<std::size_t>(column++)]);
    r.ambient = theta(column);
    r.ambientSigma = spreadOf(resampled[static_cast<std::size_t>(column)]);
    return r;
}

}  // namespace

FloorSplit splitFloor(const std::array<std::vector<FloorSample>, 3>& channels,
                      const FloorSplitOptions& options) {
    FloorSplit split;
    split.cameraBlackGiven = options.cameraBlack.has_value();
    split.separable = true;
    for (std::size_t k = 0; k < 3; ++k) {
        const double known = options.cameraBlack ? (*options.cameraBlack)[k] : kNaN;
        const ChannelResult r = splitChannel(channels[k], known, options, options.seed + k);
        split.cameraBlack[k] = r.black;
        split.cameraBlackSigma[k] = r.blackSigma;
        split.projectorBlack[k] = r.projectorBlack;
        split.projectorBlackSigma[k] = r.projectorBlackSigma;
        split.ambient[k] = r.ambient;
        split.ambientSigma[k] = r.ambientSigma;
        split.floor[k] = r.floor;
        split.ambientAtMost[k] = r.ambientAtMost;
        split.ambientLeverage[k] = r.leverage;
        split.separable = split.separable && std::isfinite(r.ambientSigma) &&
                          r.ambientSigma <= options.maxAmbientSigma * r.ambientAtMost &&
                          r.leverage >= options.minLeverage;
        if (k == 0) {
            split.pixels = r.pixels;
            split.blocks = r.blocks;
        }
    }
    if (!split.separable) {
        for (std::size_t k = 0; k < 3; ++k) {
            split.ambient[k] = split.ambientSigma[k] = kNaN;
            if (!split.cameraBlackGiven) {
                split.cameraBlack[k] = split.cameraBlackSigma[k] = kNaN;
            }
        }
    }
    return split;
}

std::string describeFloorSplit(const FloorSplit& split, const FloorSplitOptions& options) {
    char text[768];
    const auto triple = [](const std::array<double, 3>& v) {
        char out[96];
        std::snprintf(out, sizeof out, "R %.4f G %.4f B %.4f", v[0], v[1], v[2]);
        return std::string(out);
    };
    const auto withErrors = [](const std::array<double, 3>& v, const std::array<double, 3>& e) {
        char out[160];
        std::snprintf(out, sizeof out, "R %.4f ± %.4f, G %.4f ± %.4f, B %.4f ± %.4f", v[0], e[0],
                      v[1], e[1], v[2], e[2]);
        return std::string(out);
    };
    const double leverage = 100 * std::max({split.ambientLeverage[0], split.ambientLeverage[1],
                                            split.ambientLeverage[2]});
    if (split.separable) {
        std::snprintf(text, sizeof text,
                      "the floor (%s of the camera's range) is the camera's black %s%s, the "
                      "projector's black %s of its full output, and the room's light %s of the "
                      "projector's full output at 1 m",
                      triple(split.floor).c_str(),
                      split.cameraBlackGiven
                          ? triple(split.cameraBlack).c_str()
                          : withErrors(split.cameraBlack, split.cameraBlackSigma).c_str(),
                      split.cameraBlackGiven ? " (given)" : "",
                      withErrors(split.projectorBlack, split.projectorBlackSigma).c_str(),
                      withErrors(split.ambient, split.ambientSigma).c_str());
    } else if (!split.cameraBlackGiven) {
        std::snprintf(text, sizeof text,
                      "the floor of %s (of the camera's range) cannot be split into the camera's "
                      "black and the room's light on this object: its albedo varies by %.1f %% "
                      "apart from the geometry (%.0f %% needed), and on so even an albedo an "
                      "offset in the camera and light in the room look alike; the room's light is "
                      "at most %s of the "
                      "projector's full output at 1 m (all of the floor); give --camera-black "
                      "(the mean of a raw frame with the lens capped) to split it",
                      triple(split.floor).c_str(), leverage, 100 * options.minLeverage,
                      triple(split.ambientAtMost).c_str());
    } else {
        std::snprintf(text, sizeof text,
                      "the floor of %s (of the camera's range) cannot be split into the "
                      "projector's black and the room's light on this object, even with the "
                      "camera's black given: its albedo F / S varies by %.1f %% apart from F "
                      "(%.0f %% needed), too little for the geometry to tell them; the room's "
                      "light is at most %s "
                      "of the projector's full output at 1 m (all of the floor above the black)",
                      triple(split.floor).c_str(), leverage, 100 * options.minLeverage,
                      triple(split.ambientAtMost).c_str());
    }
    return text;
}

}  // namespace vpe::radiometry
