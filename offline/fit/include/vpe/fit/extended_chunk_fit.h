// SPDX-License-Identifier: MIT
// The extended model's per-chunk fit: I(l) = T(l) · f(θd, θs), alternating between
//   - f, the transferable Fourier BRDF (paper eq. 19), fitted on y / T with weights T²
//     (the same SIMD kernel), so shadowed samples stop dragging the material down; and
//   - T, the texel's light-transport factor over the rig's light directions (cast shadows,
//     interreflection), a ridge-regularized spherical-harmonic fit towards T ≡ 1 on
//     luminance, each texel's ridge its own where its lights ask for a weaker one. T then
//     takes a colour: each channel's T is fitted to that channel, pulled towards the
//     luminance T by the same ridge, and the three keep T's luminance; f is fitted on each
//     channel's y / T_c.
// Shadows only darken, so f is first refitted as an upper envelope (Tukey weights on
// residuals far below the model) before T is introduced; otherwise the alternation settles
// where f has absorbed the shadows and T ≈ 1. Saturated samples are censored: they count
// only while the model predicts less than the clipped value (a lower bound).
#pragma once

#include <array>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/sample_band.h"
#include "vpe/fit/normal_equations.h"
#include "vpe/model/light_transport.h"

namespace vpe::fit {

struct ExtendedFitSettings {
    int harmonics = 10;
    double lambda = 3.14;
    AccumulationPrecision precision = AccumulationPrecision::kFloatBlocks;
    int rounds = 4;               // BRDF fits: f, (T, f) × 3 with shadow weights
    double transportRidge = 1.0;  // relative to the average sample's weight in the T fit
    // Each texel may take a weaker ridge where its own lights ask for it (the leave-one-out
    // rule of extended_chunk_fit.cpp); false: every texel takes transportRidge.
    bool texelRidges = true;
    bool colourTransport = true;  // false: T stays grey (every channel the luminance T)
    // Tukey cutoff for darker-than-model residuals, in robust σ. Measured on SynthRTI and on
    // a synthetic horizon shadow: 3σ keeps the material clean but loses ~1 dB on held-out
    // lights; 8σ keeps it as clean and loses ~0.1 dB.
    double shadowCutoff = 8.0;
    double minimumTransport = 0.02;  // T below this drops the sample from the f fit
    // Normals refined by the fit itself (fitChunkExtendedRefiningNormals): a pattern search
    // over each texel's tilt, 4 directions at this angle, halved normalSearchSteps − 1 times.
    // 0 keeps the normals as given.
    double normalSearchDegrees = 0;
    int normalSearchSteps = 3;
};

struct ExtendedChunkSolution {
    ChunkSolution brdf;
    float transport[kLanes][model::kTransportValues];  // [lane][channel][term]
    // Σ w (y − T E f)² over the lane's usable training samples and RGB, in linear radiance
    // (censored samples the model already reaches count zero): what the normal search lowers.
    double trainingError[kLanes];
    // The ridge each lane's last T fit took (the texel's own, or the settings').
    double transportRidge[kLanes];
};

// Light data shared by all chunks of a capture.
struct ExtendedLightTable {
    // The distinct entries of a symmetric kTransportTerms² matrix, row by row (upper triangle).
    static constexpr int kTransportPairs =
        model::kTransportTerms * (model::kTransportTerms + 1) / 2;
    std::vector<std::array<double, model::kTransportTerms>> transportBasis;  // per sample
    std::vector<std::array<double, kTransportPairs>> transportOuter;         // h hᵀ, per sample
    explicit ExtendedLightTable(const capture::Capture& capture);
};

// `laneRidges` (kLanes values), when given, are T's ridges as they are: each texel's own ridge
// is not chosen again (a normal search's tilts keep the one their centre's fit chose).
void fitChunkExtended(const capture::Capture& capture, const ExtendedLightTable& table,
                      const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                      const KernelLightSet& lights, const capture::SampleBand& band, int row,
                      int x0, const ExtendedFitSettings& settings, ExtendedChunkSolution& out,
                      const double* laneRidges = nullptr);

// The same fit, then (with settings.normalSearchDegrees > 0) each lane's normal refined: a
// photometric-stereo normal is a Lambertian estimate that drops the darkest samples, and raking
// lights, where the model is most sensitive to the tilt, are among them. Every tilt of the
// pattern is tried from the first fit, under the ridges it chose (choosing a texel's ridge is
// most of a T fit's cost; a tilt of a few degrees does not move it): T's luminance and f once,
// T's colour carried from the first fit except in the last step; a lane keeps the normal,
// BRDF and T of the lowest training error, fitted whole once more. `geometry`'s normals are
// replaced by the chosen ones.
void fitChunkExtendedRefiningNormals(const capture::Capture& capture,
                                     const ExtendedLightTable& table, ChunkGeometry& geometry,
                                     const bool (&laneValid)[kLanes], const KernelLightSet& lights,
                                     const capture::SampleBand& band, int row, int x0,
                                     const ExtendedFitSettings& settings,
                                     ExtendedChunkSolution& out);

}  // namespace vpe::fit
