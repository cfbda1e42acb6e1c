// SPDX-License-Identifier: MIT
// How closely the nodes of a show agree, from their `vpe-player --light-log` files (one sample
// per frame: the presentation time on CLOCK_REALTIME and the light drawn for it).
//
// Agreement as time: for each frame of a node, the lag is the smallest |δ| such that the
// reference node's light δ earlier or later (linearly interpolated between its frames) is where
// this node's light is, within a tolerance. Two nodes showing the same light at the same
// moment lag 0; a node running 5 ms behind during a move lags 5 ms; a still light agrees at
// δ = 0 whatever its speed before. When no δ within the window brings the reference to this
// node's light, the frame is apart (the lag counts as the window). The distance between two
// lights is the angle between their directions, a difference of distance counting as the angle
// it would subtend across. The reference is known at its own frames only: where its path bends
// between two of them (a knob turned back), the straight line between them cuts the corner,
// and as much as the bends of the frames around it allow is allowed more there
// (interpolationAllowanceDeg; on a smooth move it blurs the lag measured by up to h²/2τ, 1.2 ms
// for 60 Hz frames and a 0.12 s smoothing).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vpe::firmware::bus::testing {

struct LightSample {
    std::int64_t tUs = 0;  // the frame's presentation time, CLOCK_REALTIME
    double azimuthDeg = 0, elevationDeg = 0, distanceM = 1;
    std::string active;
};
using LightTrack = std::vector<LightSample>;

// Reads a light log. Throws std::runtime_error naming the file and line.
LightTrack readLightLog(const std::filesystem::path& path);

// Degrees between two lights (see above).
double lightDistanceDeg(const LightSample& a, const LightSample& b);

// The track at time t, interpolated between the frames around it (azimuth the short way);
// empty outside the track.
std::optional<LightSample> lightAt(const LightTrack& track, std::int64_t tUs);

// How far the track's path may leave the straight line between its two frames around t, from
// the bends (second differences, degrees) at those frames: a·b/(a + b), exact for a corner.
double interpolationAllowanceDeg(const LightTrack& track, std::int64_t tUs);

struct AgreementOptions {
    double windowMs = 100;       // the lags searched, both ways
    double stepMs = 0.25;        // their spacing
    double toleranceDeg = 0.02;  // lights this close are the same
};

struct Agreement {
    std::vector<double> lagsMs;  // one per frame compared
    std::size_t apart = 0;       // frames no lag in the window explained
    double percentile(double q) const;
};

// The frames of `other` presented in [fromUs, toUs] (with the reference covering the window
// around them), against `reference`.
Agreement compareTracks(const LightTrack& reference, const LightTrack& other, std::int64_t fromUs,
                        std::int64_t toUs, const AgreementOptions& options = {});

// The first frame time ≥ fromUs from which `other` agrees with `reference` within maxLagMs
// through toUs; empty when it never settles. A lone late frame between two that agree (a
// frame presented late on a busy machine: its light was right, its time slipped) does not
// unsettle it; two in a row do. The lone ones still count in compareTracks' percentiles.
std::optional<std::int64_t> settledFrom(const LightTrack& reference, const LightTrack& other,
                                        std::int64_t fromUs, std::int64_t toUs, double maxLagMs,
                                        const AgreementOptions& options = {});

// The times a track starts moving after standing still: the first frame that moves more than
// moveDeg from the frame before, after stillFrames frames that each moved less than stillDeg.
std::vector<std::int64_t> motionOnsets(const LightTrack& track, double stillDeg = 0.0005,
                                       int stillFrames = 10, double moveDeg = 0.002);

// The largest gap between consecutive frames in [fromUs, toUs], in ms (a node that stopped
// drawing shows a gap).
double largestGapMs(const LightTrack& track, std::int64_t fromUs, std::int64_t toUs);

}  // namespace vpe::firmware::bus::testing
