// SPDX-License-Identifier: MIT
#include "light_log_agreement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

namespace vpe::firmware::bus::testing {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

std::array<double, 3> direction(const LightSample& s) {
    const double az = s.azimuthDeg * kDegree, el = s.elevationDeg * kDegree;
    return {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
}

}  // namespace

LightTrack readLightLog(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) {
        throw std::runtime_error(path.string() + ": cannot read");
    }
    LightTrack track;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.empty()) {
            continue;
        }
        const nlohmann::json sample = nlohmann::json::parse(line, nullptr, false);
        // A node killed outright may leave half a line at the end: the rest is read.
        if (sample.is_discarded() || !sample.is_object() || !sample.contains("t_us")) {
            if (in.peek() == EOF) {
                break;
            }
            throw std::runtime_error(path.string() + ":" + std::to_string(number) +
                                     ": not a light-log line");
        }
        LightSample s;
        s.tUs = sample.at("t_us").get<std::int64_t>();
        s.azimuthDeg = sample.at("azimuth").get<double>();
        s.elevationDeg = sample.at("elevation").get<double>();
        s.distanceM = sample.at("distance").get<double>();
        s.active = sample.value("active", "");
        if (!track.empty() && s.tUs < track.back().tUs) {
            throw std::runtime_error(path.string() + ":" + std::to_string(number) +
                                     ": time goes backwards");
        }
        track.push_back(std::move(s));
    }
    return track;
}

double lightDistanceDeg(const LightSample& a, const LightSample& b) {
    const auto u = direction(a), v = direction(b);
    const std::array<double, 3> cross{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                      u[0] * v[1] - u[1] * v[0]};
    const double sine = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
    const double cosine = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    const double angle = std::atan2(sine, cosine) / kDegree;
    const double across = std::abs(a.distanceM - b.distanceM) /
                          std::max(0.5 * (a.distanceM + b.distanceM), 1e-6) / kDegree;
    return std::max(angle, across);
}

std::optional<LightSample> lightAt(const LightTrack& track, std::int64_t tUs) {
    if (track.empty() || tUs < track.front().tUs || tUs > track.back().tUs) {
        return std::nullopt;
    }
    const auto after =
        std::lower_bound(track.begin(), track.end(), tUs,
                         [](const LightSample& s, std::int64_t t) { return s.tUs < t; });
    if (after->tUs == tUs || after == track.begin()) {
        return *after;
    }
    const LightSample& a = *(after - 1);
    const LightSample& b = *after;
    const double w = static_cast<double>(tUs - a.tUs) / static_cast<double>(b.tUs - a.tUs);
    LightSample s = a;
    s.tUs = tUs;
    s.azimuthDeg = a.azimuthDeg + w * std::remainder(b.azimuthDeg - a.azimuthDeg, 360.0);
    s.elevationDeg = a.elevationDeg + w * (b.elevationDeg - a.elevationDeg);
    s.distanceM = a.distanceM + w * (b.distanceM - a.distanceM);
    return s;
}

double interpolationAllowanceDeg(const LightTrack& track, std::int64_t tUs) {
    if (track.size() < 3) {
        return 0;
    }
    const auto after =
        std::lower_bound(track.begin(), track.end(), tUs,
                         [](const LightSample& s, std::int64_t t) { return s.tUs < t; });
    const auto index = static_cast<std::size_t>(std::max<std::ptrdiff_t>(after - track.begin(), 1));
    const auto bend = [&](std::size_t k) {
        k = std::clamp<std::size_t>(k, 1, track.size() - 2);
        const LightSample &a = track[k - 1], &b = track[k], &c = track[k + 1];
        const double dAz = std::remainder(c.azimuthDeg - b.azimuthDeg, 360.0) -
                           std::remainder(b.azimuthDeg - a.azimuthDeg, 360.0);
        const double dEl = (c.elevationDeg - b.elevationDeg) - (b.elevationDeg - a.elevationDeg);
        return std::hypot(dAz * std::cos(b.elevationDeg * kDegree), dEl);
    };
    // A corner at k within an interval of h, between slopes v1 and v2, leaves the chord by
    // k(h − k)/h·|v2 − v1|, while the bends at the interval's ends are (h − k)|v2 − v1| and
    // k|v2 − v1|: the corner's distance is a·b/(a + b) of the two bends a, b, exactly. A smooth
    // curve leaves it by a quarter of that.
    const double a = bend(index - 1), b = bend(index);
    return a + b > 0 ? a * b / (a + b) : 0.0;
}

double Agreement::percentile(double q) const {
    if (lagsMs.empty()) {
        return 0;
    }
    std::vector<double> sorted = lagsMs;
    std::sort(sorted.begin(), sorted.end());
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

namespace {

// The lag of one frame, or empty when the reference does not cover the window around it.
std::optional<double> lagOf(const LightTrack& reference, const LightSample& frame,
                            const AgreementOptions& options, bool& apart) {
    const auto windowUs = static_cast<std::int64_t>(options.windowMs * 1000);
    if (frame.tUs - windowUs < reference.front().tUs ||
        frame.tUs + windowUs > reference.back().tUs) {
        return std::nullopt;
    }
    const int steps = static_cast<int>(std::lround(options.windowMs / options.stepMs));
    std::vector<double> distances(static_cast<std::size_t>(2 * steps + 1));
    double nearest = 1e9;
    for (int k = -steps; k <= steps; ++k) {
        const auto t =
            frame.tUs + static_cast<std::int64_t>(std::llround(k * options.stepMs * 1000));
        const double d = std::max(0.0, lightDistanceDeg(*lightAt(reference, t), frame) -
                                           interpolationAllowanceDeg(reference, t));
        distances[static_cast<std::size_t>(k + steps)] = d;
        nearest = std::min(nearest, d);
    }
    apart = nearest > options.toleranceDeg;
    if (apart) {
        return options.windowMs;
    }
    // The smallest |δ| as close as the closest (a still light matches at δ = 0).
    const double enough = nearest + 0.1 * options.toleranceDeg;
    for (int k = 0; k <= steps; ++k) {
        if (distances[static_cast<std::size_t>(steps + k)] <= enough ||
            distances[static_cast<std::size_t>(steps - k)] <= enough) {
            return k * options.stepMs;
        }
    }
    return options.windowMs;
}

}  // namespace

Agreement compareTracks(const LightTrack& reference, const LightTrack& other, std::int64_t fromUs,
                        std::int64_t toUs, const AgreementOptions& options) {
    Agreement agreement;
    if (reference.size() < 2) {
        return agreement;
    }
    for (const LightSample& frame : other) {
        if (frame.tUs < fromUs || frame.tUs > toUs) {
            continue;
        }
        bool apart = false;
        if (const auto lag = lagOf(reference, frame, options, apart)) {
            agreement.lagsMs.push_back(*lag);
            agreement.apart += apart ? 1 : 0;
        }
    }
    return agreement;
}

std::optional<std::int64_t> settledFrom(const LightTrack& reference, const LightTrack& other,
                                        std::int64_t fromUs, std::int64_t toUs, double maxLagMs,
                                        const AgreementOptions& options) {
    if (reference.size() < 2) {
        return std::nullopt;
    }
    // The lag of each frame in the window (empty: not comparable).
    std::vector<std::pair<std::int64_t, std::optional<double>>> lags;
    for (const LightSample& frame : other) {
        if (frame.tUs < fromUs || frame.tUs > toUs) {
            continue;
        }
        bool apart = false;
        lags.emplace_back(frame.tUs, lagOf(reference, frame, options, apart));
    }
    const auto agrees = [&](std::size_t i) {
        return i < lags.size() && lags[i].second && *lags[i].second <= maxLagMs;
    };
    std::optional<std::int64_t> settled;
    bool any = false;
    for (std::size_t i = 0; i < lags.size(); ++i) {
        if (!lags[i].second) {
            continue;
        }
        any = true;
        if (agrees(i)) {
            if (!settled) {
                settled = lags[i].first;
            }
        } else if (!(settled && i + 1 < lags.size() && agrees(i - 1) && agrees(i + 1))) {
            settled.reset();
        }
    }
    return any ? settled : std::nullopt;
}

std::vector<std::int64_t> motionOnsets(const LightTrack& track, double stillDeg, int stillFrames,
                                       double moveDeg) {
    std::vector<std::int64_t> onsets;
    int still = 0;
    for (std::size_t i = 1; i < track.size(); ++i) {
        const double moved = lightDistanceDeg(track[i - 1], track[i]);
        if (moved > moveDeg && still >= stillFrames) {
            onsets.push_back(track[i].tUs);
        }
        still = moved < stillDeg ? still + 1 : 0;
    }
    return onsets;
}

double largestGapMs(const LightTrack& track, std::int64_t fromUs, std::int64_t toUs) {
    double largest = 0;
    for (std::size_t i = 1; i < track.size(); ++i) {
        if (track[i].tUs >= fromUs && track[i - 1].tUs <= toUs) {
            largest =
                std::max(largest, static_cast<double>(track[i].tUs - track[i - 1].tUs) / 1000);
        }
    }
    return largest;
}

}  // namespace vpe::firmware::bus::testing
