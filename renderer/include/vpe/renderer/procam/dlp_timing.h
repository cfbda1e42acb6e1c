// SPDX-License-Identifier: MIT
// DlpTiming: how a DLP projector makes a level out of binary bit-planes within each frame, and
// what a camera that exposes for part of a frame, or for a number of frames that is not whole,
// integrates of it (renderer/procam/README.md, "A DLP projector and a short exposure").
#pragma once

#include <cstdint>

namespace vpe::renderer::procam {

// The order a frame shows its 8 bit-planes in; plane k lasts 2^k/255 of the frame.
enum class DlpBitOrder : std::uint8_t {
    kMsbFirst,  // plane 7 (128/255 of the frame), then 6, …, 0
    kLsbFirst,  // plane 0 (1/255), then 1, …, 7
};

// A DLP projector's timing as the camera meets it. Each mirror is on or off; a level is the
// share of the frame it is on, in binary bit-planes. A camera that integrates whole frames sees
// that share exactly; one that integrates a window of another length sees the mirror's mean over
// the window alone, which depends on where the window starts.
struct DlpTiming {
    // The camera's exposure in frame periods (0.3: under a third of a frame; 1.5: a frame and a
    // half). 0: off, the camera sees every level's time-average (a whole-frame exposure).
    double exposureFrames = 0;
    DlpBitOrder order = DlpBitOrder::kMsbFirst;

    bool enabled() const { return exposureFrames > 0; }
};

// The mean mirror state over the window [start, start + exposureFrames) frame periods (start in
// [0, 1), 0 at the first bit-plane's start) for a pixel whose frame-average is `duty` in [0, 1]:
// the light after the projector's response, as a real DLP puts its degamma into the bit-plane
// weights. duty·255 falls between two 8-bit codes; the projector dithers between them (in time
// and space) so that their mix has the right mean, and the window sees that mix:
// (1 − f)·window(⌊c⌋) + f·window(⌊c⌋ + 1). Exactly `duty` for 0, 1 and any whole number of
// frames. Needs timing.enabled().
double dlpWindowDuty(const DlpTiming& timing, double duty, double start);

// Where frame `frame`'s exposure window starts in the projector's frame, in [0, 1) frame
// periods: a pure function of (seed, frame), uniform, independent of the sensor's noise.
double dlpWindowStart(std::uint64_t seed, std::uint64_t frame);

}  // namespace vpe::renderer::procam
