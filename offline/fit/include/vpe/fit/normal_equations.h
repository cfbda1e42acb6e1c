// SPDX-License-Identifier: MIT
// The per-pixel normal equations of the Fourier BRDF fit (paper eq. 19), built for kLanes
// pixels at a time from O(N·M) sums via product-to-sum identities, and solved batched.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "vpe/proto/fourier_brdf.h"

namespace vpe::fit {

// Pixels per kernel call. The kernels take them in slices of one vector of the CPU's SIMD target
// (16 floats on AVX-512, 8 on AVX2, 4 on SSE4 and NEON).
inline constexpr int kLanes = 16;
inline constexpr int kChannels = 3;  // RGB
inline constexpr int kMaxCoefficients = proto::coefficientCount(proto::kMaxHarmonics);

// One capture light as the kernel sees it.
struct KernelLight {
    float x = 0, y = 0, z = 0;      // unit direction towards the light, or its position
    float inverseIntensity = 1.0f;  // observations are divided by the light's intensity
};

struct KernelLightSet {
    const KernelLight* lights = nullptr;
    int count = 0;
    bool point = false;  // positions with inverse-square falloff instead of directions
    // Point lights: irradiance is normalized to a light at this distance.
    float referenceDistanceSquared = 1.0f;
};

// Geometry of kLanes pixels, structure of arrays.
struct ChunkGeometry {
    alignas(64) float normal[3][kLanes];
    alignas(64) float view[3][kLanes];      // unit vector towards the viewer
    alignas(64) float position[3][kLanes];  // surface point, for point lights
};

// Observations of kLanes pixels: value(s, c, lane) = values[s * sampleStride +
// c * channelStride + lane] and weight(s, lane) = weights[s * weightStride + lane].
struct ChunkObservations {
    const float* values = nullptr;
    std::size_t sampleStride = 0;
    std::size_t channelStride = 0;
    // 0 drops a sample (decode failure, mask, censoring); null: every sample has weight 1.
    const float* weights = nullptr;
    std::size_t weightStride = 0;
};

// The sums every normal matrix with up to `harmonics` harmonics is assembled from: with
// c = cos θs, d = max(cos θd, 0), w the sample weight and y the normalized observation,
//   cosine[k] = Σ w cos kθs (k = 0..2M)      sine[k] = Σ w sin kθs (k = 1..2M)
//   lambertCosine[m] = Σ w d cos mθs          lambertSine[m] = Σ w d sin mθs (m = 0..M)
//   lambertSquare = Σ w d²                    projection[c][j] = Σ w y_c φ_j
//   squares[c] = Σ w y_c²                     count = Σ w
// Stored in double: accumulated in float over short blocks of samples, then added here.
struct NormalEquationSums {
    int harmonics = 0;
    // Relative rounding error of the sums (float blocks ~1e-7, double ~1e-13). The solve adds
    // this much of the mean diagonal as a ridge: invisible beside any real λ, but it turns a
    // rank-deficient system (λ = 0 with the nearly redundant cos/sin basis) into its
    // minimum-norm least-squares solution instead of a failure.
    double roundingLevel = 0;
    double cosine[2 * proto::kMaxHarmonics + 1][kLanes];
    double sine[2 * proto::kMaxHarmonics + 1][kLanes];
    double lambertCosine[proto::kMaxHarmonics + 1][kLanes];
    double lambertSine[proto::kMaxHarmonics + 1][kLanes];
    double lambertSquare[kLanes];
    double projection[kChannels][kMaxCoefficients][kLanes];
    double squares[kChannels][kLanes];
    double count[kLanes];
};

struct ChunkSolution {
    // Entries 0 .. 2M + 1 of the last solve; entries past them are left as they were.
    float coefficients[kLanes][kChannels][kMaxCoefficients];
    float rms[kLanes][kChannels];  // residual RMS over the used samples, normalized units
    bool valid[kLanes];
};

// How the sums are accumulated. The model's basis is nearly redundant on θs ∈ [0, π]
// (cos mθ and sin mθ each span it alone), so an unregularized system is ill-conditioned and
// amplifies rounding: float blocks (2x faster, ~1e-7 relative per sum) suit regularized fits,
// double suits λ ≈ 0 and research sweeps.
enum class AccumulationPrecision { kFloatBlocks, kDouble };

// Accumulates the sums for `harmonics` (≤ kMaxHarmonics) over all samples.
void accumulateNormalEquations(const ChunkGeometry& geometry, const KernelLightSet& lights,
                               const ChunkObservations& observations, int harmonics,
                               AccumulationPrecision precision, NormalEquationSums& sums);

// Assembles the (2M+2)² normal matrix of one lane, M ≤ sums.harmonics, without the
// smoothness term: row-major into matrix[K * K].
void assembleNormalMatrix(const NormalEquationSums& sums, int lane, int harmonics, double* matrix);

// Solves (AᵀWA + λR) x = AᵀWy for every lane and channel with M ≤ sums.harmonics. A lane is
// invalid when it has fewer than 2M + 2 samples or a singular system; its output is zero.
void solveNormalEquations(const NormalEquationSums& sums, int harmonics, double lambda,
                          ChunkSolution& solution);

// The SIMD targets (Highway's HWY_* bits) the kernels above are compiled for and this CPU
// runs, best first. The best one runs unless hwy::SetSupportedTargetsForTest narrows the
// choice, as the tests and the benchmark do to run each.
std::vector<std::int64_t> kernelTargets();
// The target the kernels dispatch to now, and its name (AVX3, AVX2, SSE4, NEON, ...; SCALAR for
// Highway's portable fallback, whichever the compiler built).
std::int64_t activeKernelTarget();
const char* kernelTargetName(std::int64_t target);
const char* activeKernelTargetName();

// Restricts every SIMD kernel of the fit, for the rest of the process, to the target called
// `name` (Highway's names, any case: AVX3 for AVX-512, AVX2, SSE4, SSSE3, SCALAR; NEON on
// arm64), so that one machine can measure the code another CPU would run. The `vpe` command
// calls it with its environment's VPE_SIMD. Throws common::InputError naming `name` and the
// choices where it is not one of kernelTargets().
void restrictKernelTarget(std::string_view name);

}  // namespace vpe::fit
