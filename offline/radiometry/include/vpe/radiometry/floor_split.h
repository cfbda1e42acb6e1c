// SPDX-License-Identifier: MIT
// splitFloor: what the camera sees with the projector at level 0 (the floor D), split into what
// the camera adds and the light that falls on the object, with how well the object's albedo and
// geometry tell them apart (docs/radiometry.md, "The ambient, apart"). Per camera channel and
// projector pixel:
//
//   D = black + projectorBlack · F + ambient · F / S
//
// black the camera's offset (the same whatever the light: its sensor's pedestal), F the irradiance
// factor (albedo × S × the camera's gain), S = cos θ / d² of the projector's light: the projector's
// light at level 0 is a share of F, and the room's light — even over a small object — reaches the
// camera as the albedo times the gain, F / S, in units of the projector's full output at 1 m.
//
// The three terms are told apart only by how F / S (the albedo) varies apart from a constant and
// apart from F (that is, from the geometry). On plaster of one albedo F / S is a constant: an
// offset in the camera and light in the room look alike, and no fit can split them. A known black
// (the mean of a frame with the lens capped) removes the offset; the geometry then splits the rest.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vpe::radiometry {

// One projector pixel's floor in one camera channel, and what explains it.
struct FloorSample {
    float floor = 0;       // D: the camera's linear signal, share of its range
    float irradiance = 0;  // F: what the channel's own primary at full output adds
    float geometry = 0;    // S = cos θ / d² of the projector's light (1 / m²)
    std::uint32_t block =
        0;  // the patch of the projector's image it lies in (the bootstrap's unit)
};

struct FloorSplitOptions {
    // The camera's black level per channel, share of its range, when it is known; else fitted.
    std::optional<std::array<double, 3>> cameraBlack;
    // Resamples of the blocks for the standard errors (neighbouring pixels' errors are not
    // independent: the stains, the blur and the interreflection are smooth).
    int bootstrap = 400;
    std::uint64_t seed = 1;
    // The split is trusted when the ambient's standard error is at most this share of the most
    // the floor allows it (ambientAtMost): the floor's room light known to ± 10 % of the floor;
    double maxAmbientSigma = 0.1;
    // and when the albedo varies apart from the other terms by at least this share of its mean
    // (ambientLeverage). The model's own errors make some such spread on plaster of one albedo
    // (interreflection, which F carries and the floor does not in the same way; the scan's
    // normals: 3.7 % on the simulated vase), and a fit on no more than that follows them: there it
    // gave 0.066 ± 0.004 for a room light of 0.058.
    double minLeverage = 0.08;
};

struct FloorSplit {
    // Per camera channel: the value and its standard error (a bootstrap over blocks of pixels).
    std::array<double, 3> cameraBlack{}, cameraBlackSigma{};        // share of the camera's range
    std::array<double, 3> projectorBlack{}, projectorBlackSigma{};  // share of F
    std::array<double, 3> ambient{}, ambientSigma{};  // the projector's full output at 1 m
    // The median floor over the object (share of the camera's range), and the most room light it
    // allows: all of the floor but the known black, the projector's black taken as 0.
    std::array<double, 3> floor{};
    std::array<double, 3> ambientAtMost{};
    // How far the room's light can be told from the other terms: the spread of the albedo F / S
    // that they do not follow, as a share of its mean. The ambient's standard error is about the
    // floor's noise over this, over √(independent blocks).
    std::array<double, 3> ambientLeverage{};
    bool cameraBlackGiven = false;
    // Every channel's ambient within maxAmbientSigma, with minLeverage. When false, ambient and
    // cameraBlack (and their errors) are NaN: only the floor, ambientAtMost and the projector's
    // black stand.
    bool separable = false;
    std::size_t pixels = 0, blocks = 0;  // of the first channel
};

// A channel with fewer than 16 usable samples (finite, F and S > 0) leaves every part NaN and
// the split not separable.
FloorSplit splitFloor(const std::array<std::vector<FloorSample>, 3>& channels,
                      const FloorSplitOptions& options = {});

// One line for people: the three parts with their errors, or that the floor cannot be split on
// this object, why (against the options it was split with), and the most room light it allows.
std::string describeFloorSplit(const FloorSplit& split, const FloorSplitOptions& options = {});

}  // namespace vpe::radiometry
