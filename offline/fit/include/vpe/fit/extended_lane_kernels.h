// SPDX-License-Identifier: MIT
// The extended fit's lane kernels: every texel (lane) of a chunk at once, for f's predictions
// and training error, T's normal equations, its ridge solves (a Cholesky factor per lane) and
// each texel's leave-one-light-out error (PRESS). Written once with Highway
// (extended_lane_kernels.cpp) and dispatched to the CPU's best SIMD target, as the BRDF's
// normal equations are. Arrays are [entry][lane], kLanes lanes an entry.
#pragma once

#include <cstdint>

#include "vpe/fit/extended_chunk_fit.h"
#include "vpe/fit/normal_equations.h"

namespace vpe::fit {

// A chunk's samples as the lane kernels read them: per sample, every lane side by side.
struct LaneSamples {
    int count = 0;
    const double* cosD = nullptr;        // [sample][lane]
    const double* cosS = nullptr;        // [sample][lane]
    const double* irradiance = nullptr;  // [sample][lane]
};

// What a chunk's training samples are, for everyLaneError: per sample and lane (weights,
// saturation) or per sample, channel and lane (values, each channel's T).
struct LaneObservations {
    const float* weights = nullptr;
    const std::uint8_t* saturated = nullptr;
    const float* values = nullptr;
    const float* transport = nullptr;
};

// The luminance samples of a chunk's T fit as the ridge choice reads them, [sample][lane]:
// weight w (0 for a sample the fit does not use), the BRDF's prediction P and the observation L.
struct LanePressSamples {
    int count = 0;
    const double* weight = nullptr;
    const double* predicted = nullptr;
    const double* observed = nullptr;
};

// Every lane's BRDF prediction of every sample, in image units: per channel, [sample][channel]
// [lane], and its luminance, [sample][lane]. Each lane with the same operations in the same
// order as one lane alone.
void predictEveryLane(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                      double* rgbOut, double* luminanceOut);

// Every lane's Σ w (y − T_c E f_c)² over its samples and channels: samples without weight, and
// clipped ones the model already reaches, count zero.
void everyLaneError(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                    const LaneObservations& observed, double (&error)[kLanes]);

// T's normal equations of every lane at once: for each channel c, a's distinct entries
// pairs[c][k][lane] = Σ_s u[s][c][lane] (h hᵀ)_k(s) and b's rights[c][t][lane] =
// Σ_s v[s][c][lane] h_t(s), h and h hᵀ each light's (ExtendedLightTable).
void sumTransportEquations(const ExtendedLightTable& table, int samples, int channels,
                           const double* u, const double* v, double* pairs, double* rights);

// Every lane's ridge solve: (A + pull I) t = b + pull · prior by Cholesky, A and b the packed
// sums of sumTransportEquations ([pair][lane], [term][lane]), pull and prior per lane ([lane],
// [term][lane]), t out as [term][lane]. `solved[lane]` is false where a pivot is not positive
// (the caller solves that lane again by LDLT).
void solveTransportLanes(const double* pairs, const double* rights, const double* pull,
                         const double* prior, double* t, bool (&solved)[kLanes]);

// Every lane's leave-one-light-out error (PRESS) of the same ridge fit, in closed form:
// Σ w ((L − P hᵀt) / (1 − w P² hᵀ(A + pull I)⁻¹h))². `valid[lane]`: the Cholesky succeeded and t
// is finite.
void transportPressLanes(const ExtendedLightTable& table, const double* pairs, const double* rights,
                         const double* pull, const double* prior, const LanePressSamples& samples,
                         double (&press)[kLanes], bool (&valid)[kLanes]);

// T of every sample for every lane from its coefficients ([term][lane]), at least 0 and at most
// 4 (the fit's own bound): out[s · kLanes + lane].
void sampleTransportLanes(const ExtendedLightTable& table, const double* t, int samples,
                          float* out);

}  // namespace vpe::fit
