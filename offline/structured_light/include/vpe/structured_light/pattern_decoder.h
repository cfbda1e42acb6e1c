// SPDX-License-Identifier: MIT
// decodePatterns: per camera pixel, which projector pixel lights it — the Gray code gives the
// quarter period, the phase shifting the position inside the period — with a robustness test
// at every step, so that pixels in shadow, saturated, or lit mostly by interreflection are
// marked, never guessed (docs/install.md, "How a scan is decoded"). A Gray code without phase
// images (a foreign sequence, proto/SCAN.md) gives whole Gray bins.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/structured_light/scan_capture.h"

namespace vpe::structured_light {

// Why a pixel has no projector coordinate.
enum class DecodeStatus : std::uint8_t {
    kDecoded = 0,
    kDark,           // the projector's light is below minDirect here (shadow, off the object)
    kSaturated,      // the white frame clipped: the phase would be wrong
    kAmbiguous,      // a Gray bit the direct light cannot tell from the global (interreflection)
    kLowModulation,  // the sinusoid is too weak: against the direct light (mixed surfaces,
                     // blur), or against the camera's noise (the position's σ > maxSigma)
    kInconsistent,   // the phase disagrees with the Gray code
    // A mixed pixel where the decoded coordinates step between neighbours (two surfaces at
    // different depths in one pixel, as a lip over a neck): its coordinate is a blend of two,
    // not a point of either surface.
    kEdge,
};
inline constexpr int kDecodeStatusCount = 7;
const char* decodeStatusName(DecodeStatus status);

// What placed a decoded pixel, the worse of its two axes: the phase at the pixel alone; the
// phase summed over a neighbourhood where the camera's noise left the pixel's own too imprecise
// (a noisy camera costs resolution there, not the pixel); or the Gray bin alone where the phase
// cannot help (too weak, or disagreeing with a code the bits hold certain).
enum class PositionSource : std::uint8_t {
    kNone = 0,
    kPhase,
    kPhaseNeighbourhood,
    kGrayBin,
};
inline constexpr int kPositionSourceCount = 4;
const char* positionSourceName(PositionSource source);

struct DecodeOptions {
    // The least direct light (white − black, as a fraction of the camera's full scale) worth
    // decoding.
    double minDirect = 0.015;
    // A white frame at or above this is clipped.
    double saturation = 0.995;
    // Noise margins of the bit tests: this many standard deviations of the camera's noise
    // (measured on the capture itself, see NoiseModel), plus a share of the pixel's
    // white − black for what the noise model does not see (response, blur).
    double noiseSigmas = 3.5;
    double relativeMargin = 0.04;
    // The phase's amplitude must reach this share of the direct light; below it the Gray bin
    // places the pixel.
    double minModulation = 0.15;
    // The phase places a pixel while the position's expected standard deviation from the
    // camera's noise (DecodedScan::precision) stays below this many projector pixels. Noisier
    // pixels sum the phase over their neighbours (3 × 3, then 5 × 5) until it does; where even
    // that does not, the Gray bin places them.
    double maxSigma = 0.25;
    // Bends of the decoded coordinates, x(left) + x(right) − 2·x on a row or a column, beyond
    // this many projector pixels and of opposite signs at two neighbours mark a step.
    double maxBend = 1.5;
    int threads = 0;
};

// The camera noise the capture itself shows: σ² = a + b·signal, fitted to how far
// pattern + inverse departs from white + black on the finest Gray pairs (where they must sum to
// the same), per brightness bin, by the median absolute deviation.
struct NoiseModel {
    double constant = 0, perSignal = 0;
    double sigma(double signal) const;
};

struct DecodedScan {
    int width = 0, height = 0;  // the camera's
    int projectorWidth = 0, projectorHeight = 0;
    std::vector<float> projectorX, projectorY;  // pixel centres at integers; NaN undecoded
    std::vector<float> direct;        // L_d: the projector's direct light, white − black share
    std::vector<float> global;        // L_g: interreflection and scatter under full white
    std::vector<float> white, black;  // the two flat frames
    // The decoded position's expected standard deviation (projector pixels, the worse axis):
    // with a phase, from the camera's noise; from a Gray code alone, the bin's width / √12.
    // NaN undecoded.
    std::vector<float> precision;
    std::vector<DecodeStatus> status;
    std::vector<PositionSource> source;     // kNone undecoded
    std::vector<std::size_t> sourceCounts;  // kPositionSourceCount entries
    // The camera's encoding the decoder undid: value = signal^(1/γ); 1 for a linear camera.
    // Measured on the capture (a pattern and its inverse add up to white + black in light, not in
    // codes).
    double cameraGamma = 1;
    // Per axis (columns, rows): how far the decoded phase's histogram departs from even (the
    // largest bin's share off the mean), and whether that distortion was undone by equalizing
    // it (a DLP's bit-planes caught by a short exposure). 0 and false without phase images.
    double phaseDistortion[2] = {0, 0};
    bool phaseEqualized[2] = {false, false};
    NoiseModel noise;
    std::vector<std::size_t> statusCounts;  // kDecodeStatusCount entries
    std::size_t decoded = 0;
    std::size_t lit = 0;  // pixels with direct light ≥ minDirect: the object the camera sees lit
};

// With phase images: the Gray bits by Xu and Aliaga's rule against white and black (which the
// sequence must show), or where that rule cannot tell, by the pair's difference against the
// global light and the camera's noise; the phase inside the bin, over a neighbourhood where the
// noise demands it, else the Gray bin (PositionSource). Without: each Gray bit from its pair's
// difference against the camera's noise at that level (DecodeOptions::noiseSigmas), one bit left
// open per axis placing the pixel on the edge between two bins; white and black where shown,
// else the pairs' highest and lowest values in their place. minModulation, maxSigma and
// saturation are the phase's and do not apply; a step between surfaces must bend the
// coordinates by maxBend beyond two bins.
//
// Throws InputError naming the capture when it cannot be decoded at all: an image missing or of
// another size (ScanCapture), a white frame (or without one, the first Gray pair) that is black
// (no projector light reaches the camera), a pair captured wrong, with a phase a white frame
// whose lit pixels are mostly saturated, or without one codes beyond the declared projector's
// width or height (divided by the code step) on over 2 % of an axis' certain codes (naming the
// manifest: the patterns were made for another size or step).
DecodedScan decodePatterns(const ScanCapture& capture, const DecodeOptions& options = {});

}  // namespace vpe::structured_light
