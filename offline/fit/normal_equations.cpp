// SPDX-License-Identifier: MIT
// Normal equations of the Fourier BRDF fit: accumulation (the hot loop, SIMD over pixels)
// and batched Cholesky solve.
#include "vpe/fit/normal_equations.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include "vpe/fit/simd_pack.h"
#include "vpe/proto/reflection_geometry.h"

namespace vpe::fit {

namespace {

using FloatPack = simd::Pack<float, kLanes>;
using DoublePack = simd::Pack<double, kLanes>;
using proto::cosineIndex;
using proto::kMaxHarmonics;
using proto::sineIndex;

// Samples summed in float before the block is added to the double sums: short enough that
// float rounding stays near 1e-7 relative, long enough to keep the flush cheap.
constexpr int kSampleBlock = 64;
constexpr int kPrefetchDistance = 8;

template <typename P>
struct Partials {
    P cosine[2 * kMaxHarmonics + 1];
    P sine[2 * kMaxHarmonics + 1];
    P lambertCosine[kMaxHarmonics + 1];
    P lambertSine[kMaxHarmonics + 1];
    P lambertSquare;
    P projection[kChannels][kMaxCoefficients];
    P squares[kChannels];
    P count;
};

template <typename P, int N>
[[gnu::always_inline]] inline void flushRows(P (&from)[N], double (&to)[N][kLanes], int rows) {
    for (int r = 0; r < rows; ++r) {
        for (int lane = 0; lane < kLanes; ++lane) {
            to[r][lane] += static_cast<double>(from[r][lane]);
        }
        from[r] = P(0);
    }
}

template <typename P>
[[gnu::always_inline]] inline void flushOne(P& from, double (&to)[kLanes]) {
    for (int lane = 0; lane < kLanes; ++lane) {
        to[lane] += static_cast<double>(from[lane]);
    }
    from = P(0);
}

// Float packs for the fast path; the exact path accumulates in double throughout.
template <typename P>
[[gnu::always_inline]] inline P loadPack(const float* p) {
    if constexpr (sizeof(typename P::Vector) == sizeof(FloatPack::Vector)) {
        return P::load(p);
    } else {
        return P(__builtin_convertvector(FloatPack::load(p).v, typename P::Vector));
    }
}

// What one sample contributes, for kLanes pixels.
template <typename P>
struct SampleTerms {
    P cosThetaS;
    P lambert;                   // max(cos θd, 0)
    P weight;                    // w
    P weightedLambert;           // w·d
    P weightedValue[kChannels];  // w·y
    P value[kChannels];          // y, normalized by the light's irradiance
};

template <typename P, bool kPointLights>
[[gnu::always_inline]] inline SampleTerms<P> sampleTerms(
    const proto::Vec3<P>& normal, const proto::Vec3<P>& view, const proto::Vec3<P>& position,
    const KernelLightSet& lights, const ChunkObservations& observations, int s, bool dummy) {
    const KernelLight& light = lights.lights[s];
    proto::Vec3<P> toLight;
    P scale;
    if constexpr (kPointLights) {
        const P dx = P(light.x) - position.x;
        const P dy = P(light.y) - position.y;
        const P dz = P(light.z) - position.z;
        const P distanceSquared = dx * dx + dy * dy + dz * dz;
        const P inverseDistance = P(1) / sqrt(distanceSquared);
        toLight = {dx * inverseDistance, dy * inverseDistance, dz * inverseDistance};
        scale = distanceSquared * P(light.inverseIntensity / lights.referenceDistanceSquared);
    } else {
        toLight = {P(light.x), P(light.y), P(light.z)};
        scale = P(light.inverseIntensity);
    }
    const proto::ReflectionAngles<P> angles = proto::reflectionAngles(normal, toLight, view);
    SampleTerms<P> terms;
    terms.cosThetaS = angles.cosThetaS;
    terms.lambert = proto::lambertBasis(angles.cosThetaD);
    terms.weight = dummy ? P(0)
                   : observations.weights
                       ? loadPack<P>(observations.weights + s * observations.weightStride)
                       : P(1);
    terms.weightedLambert = terms.weight * terms.lambert;
    const float* values = observations.values + s * observations.sampleStride;
    for (int c = 0; c < kChannels; ++c) {
        terms.value[c] = loadPack<P>(values + c * observations.channelStride) * scale;
        terms.weightedValue[c] = terms.weight * terms.value[c];
    }
    return terms;
}

// Harmonics m0 .. m0 + G − 1 over one block of samples, with their accumulators held in
// registers: each sample's recurrence state is loaded, advanced G steps and stored back, so
// memory traffic is per group of harmonics, not per accumulator update. `full` adds the
// Lambert and projection sums (harmonics ≤ M); beyond M only the plain sums continue.
template <int G, bool kFull, typename P>
[[gnu::always_inline]] inline void accumulateHarmonicGroup(const SampleTerms<P>* terms,
                                                           proto::HarmonicRecurrence<P>* state,
                                                           int count, int m0, Partials<P>& p) {
    constexpr int kSums = kFull ? 4 + 2 * kChannels : 2;
    P acc[G][kSums];
    for (int j = 0; j < G; ++j) {
        for (int i = 0; i < kSums; ++i) {
            acc[j][i] = P(0);
        }
    }
    for (int s = 0; s < count; ++s) {
        const SampleTerms<P>& t = terms[s];
        proto::HarmonicRecurrence<P>& h = state[s];
        for (int j = 0; j < G; ++j) {
            const P c = h.cosine();
            const P sn = h.sine();
            h.next();
            acc[j][0] += t.weight * c;
            acc[j][1] += t.weight * sn;
            if constexpr (kFull) {
                acc[j][2] += t.weightedLambert * c;
                acc[j][3] += t.weightedLambert * sn;
                for (int k = 0; k < kChannels; ++k) {
                    acc[j][4 + 2 * k] += t.weightedValue[k] * c;
                    acc[j][5 + 2 * k] += t.weightedValue[k] * sn;
                }
            }
        }
    }
    for (int j = 0; j < G; ++j) {
        const int m = m0 + j;
        p.cosine[m] += acc[j][0];
        p.sine[m] += acc[j][1];
        if constexpr (kFull) {
            p.lambertCosine[m] += acc[j][2];
            p.lambertSine[m] += acc[j][3];
            for (int k = 0; k < kChannels; ++k) {
                p.projection[k][cosineIndex(m)] += acc[j][4 + 2 * k];
                p.projection[k][sineIndex(m)] += acc[j][5 + 2 * k];
            }
        }
    }
}

template <typename P, bool kPointLights>
[[gnu::always_inline]] inline void accumulateSamples(const ChunkGeometry& geometry,
                                                     const KernelLightSet& lights,
                                                     const ChunkObservations& observations,
                                                     int harmonics, NormalEquationSums& sums) {
    const int coefficients = proto::coefficientCount(harmonics);
    const int gramHarmonics = 2 * harmonics;
    const proto::Vec3<P> normal{loadPack<P>(geometry.normal[0]), loadPack<P>(geometry.normal[1]),
                                loadPack<P>(geometry.normal[2])};
    const proto::Vec3<P> view{loadPack<P>(geometry.view[0]), loadPack<P>(geometry.view[1]),
                              loadPack<P>(geometry.view[2])};
    proto::Vec3<P> position{P(0), P(0), P(0)};
    if constexpr (kPointLights) {
        position = {loadPack<P>(geometry.position[0]), loadPack<P>(geometry.position[1]),
                    loadPack<P>(geometry.position[2])};
    }
    // Float packs keep two harmonics' ten accumulators in registers; double packs are two
    // registers each, so one.
    constexpr int kPair = sizeof(typename P::Vector) == sizeof(FloatPack::Vector) ? 2 : 1;

    // Only the rows this M uses are cleared (the full arrays are sized for kMaxHarmonics);
    // flushing clears them again after each block.
    Partials<P> partial;
    for (int k = 0; k <= gramHarmonics; ++k) {
        partial.cosine[k] = P(0);
        partial.sine[k] = P(0);
    }
    for (int m = 0; m <= harmonics; ++m) {
        partial.lambertCosine[m] = P(0);
        partial.lambertSine[m] = P(0);
    }
    for (int c = 0; c < kChannels; ++c) {
        for (int j = 0; j < coefficients; ++j) {
            partial.projection[c][j] = P(0);
        }
        partial.squares[c] = P(0);
    }
    partial.lambertSquare = P(0);
    partial.count = P(0);
    SampleTerms<P> terms[kSampleBlock];
    alignas(64) unsigned char stateStorage[kSampleBlock * sizeof(proto::HarmonicRecurrence<P>)];
    auto* state = reinterpret_cast<proto::HarmonicRecurrence<P>*>(stateStorage);
    for (int blockBegin = 0; blockBegin < lights.count; blockBegin += kSampleBlock) {
        const int count = std::min(lights.count - blockBegin, kSampleBlock);
        for (int i = 0; i < count; ++i) {
            // The band streams from memory at ~5 GB/s; ask for samples a few ahead.
            const int ahead = blockBegin + i + kPrefetchDistance;
            if (ahead < lights.count) {
                const float* next = observations.values + ahead * observations.sampleStride;
                for (std::size_t offset = 0; offset < 3 * kLanes; offset += 16) {
                    __builtin_prefetch(next + offset);
                }
                if (observations.weights) {
                    __builtin_prefetch(observations.weights + ahead * observations.weightStride);
                }
            }
            terms[i] = sampleTerms<P, kPointLights>(normal, view, position, lights, observations,
                                                    blockBegin + i, false);
            new (&state[i]) proto::HarmonicRecurrence<P>(terms[i].cosThetaS);
            const SampleTerms<P>& t = terms[i];
            partial.count += t.weight;
            partial.cosine[0] += t.weight;
            partial.lambertSquare += t.weightedLambert * t.lambert;
            partial.lambertCosine[0] += t.weightedLambert;
            for (int c = 0; c < kChannels; ++c) {
                partial.squares[c] += t.weightedValue[c] * t.value[c];
                partial.projection[c][proto::kLambertIndex] += t.weightedValue[c] * t.lambert;
                partial.projection[c][proto::kConstantIndex] +=
                    t.weightedValue[c] * P(proto::kConstantBasis);
            }
        }
        int m = 1;
        for (; m + kPair - 1 <= harmonics; m += kPair) {
            accumulateHarmonicGroup<kPair, true>(terms, state, count, m, partial);
        }
        for (; m <= harmonics; ++m) {
            accumulateHarmonicGroup<1, true>(terms, state, count, m, partial);
        }
        // Products of two harmonics reach 2M: only the plain sums continue.
        for (; m + 3 <= gramHarmonics; m += 4) {
            accumulateHarmonicGroup<4, false>(terms, state, count, m, partial);
        }
        for (; m <= gramHarmonics; ++m) {
            accumulateHarmonicGroup<1, false>(terms, state, count, m, partial);
        }
        flushRows(partial.cosine, sums.cosine, gramHarmonics + 1);
        flushRows(partial.sine, sums.sine, gramHarmonics + 1);
        flushRows(partial.lambertCosine, sums.lambertCosine, harmonics + 1);
        flushRows(partial.lambertSine, sums.lambertSine, harmonics + 1);
        flushOne(partial.lambertSquare, sums.lambertSquare);
        for (int c = 0; c < kChannels; ++c) {
            flushRows(partial.projection[c], sums.projection[c], coefficients);
            flushOne(partial.squares[c], sums.squares[c]);
        }
        flushOne(partial.count, sums.count);
    }
}

VPE_KERNEL_CLONES
void accumulateFast(const ChunkGeometry& geometry, const KernelLightSet& lights,
                    const ChunkObservations& observations, int harmonics,
                    NormalEquationSums& sums) {
    if (lights.point) {
        accumulateSamples<FloatPack, true>(geometry, lights, observations, harmonics, sums);
    } else {
        accumulateSamples<FloatPack, false>(geometry, lights, observations, harmonics, sums);
    }
}

VPE_KERNEL_CLONES
void accumulateExact(const ChunkGeometry& geometry, const KernelLightSet& lights,
                     const ChunkObservations& observations, int harmonics,
                     NormalEquationSums& sums) {
    if (lights.point) {
        accumulateSamples<DoublePack, true>(geometry, lights, observations, harmonics, sums);
    } else {
        accumulateSamples<DoublePack, false>(geometry, lights, observations, harmonics, sums);
    }
}

// One entry of the normal matrix from the sums (product-to-sum identities), for T = double
// (one lane) or DoublePack (all lanes); get(row) reads a [kLanes] row of the sums.
template <typename T, typename Get>
[[gnu::always_inline]] inline T normalMatrixEntry(const NormalEquationSums& sums, int i, int j,
                                                  Get get) {
    if (i > j) {
        std::swap(i, j);
    }
    constexpr double kHalf = 0.5;
    const T r2 = T(proto::kConstantBasis);
    auto cosSum = [&](int k) { return get(sums.cosine[k < 0 ? -k : k]); };
    auto sinSum = [&](int k) {
        if (k == 0) {
            return T(0.0);
        }
        return k > 0 ? get(sums.sine[k]) : T(0.0) - get(sums.sine[-k]);
    };
    if (i == proto::kLambertIndex) {
        if (j == proto::kLambertIndex) {
            return get(sums.lambertSquare);
        }
        if (j == proto::kConstantIndex) {
            return get(sums.lambertCosine[0]) * r2;
        }
        return (j % 2 == 0) ? get(sums.lambertCosine[j / 2]) : get(sums.lambertSine[j / 2]);
    }
    if (i == proto::kConstantIndex) {
        if (j == proto::kConstantIndex) {
            return cosSum(0) * T(kHalf);
        }
        return ((j % 2 == 0) ? cosSum(j / 2) : sinSum(j / 2)) * r2;
    }
    const int a = i / 2;
    const int b = j / 2;
    const bool aCos = i % 2 == 0;
    const bool bCos = j % 2 == 0;
    if (aCos && bCos) {
        return (cosSum(a - b) + cosSum(a + b)) * T(kHalf);
    }
    if (!aCos && !bCos) {
        return (cosSum(a - b) - cosSum(a + b)) * T(kHalf);
    }
    // cos(pθ) sin(qθ) = ½ [sin((q+p)θ) + sin((q−p)θ)]
    const int p = aCos ? a : b;
    const int q = aCos ? b : a;
    return (sinSum(q + p) + sinSum(q - p)) * T(kHalf);
}

}  // namespace

void accumulateNormalEquations(const ChunkGeometry& geometry, const KernelLightSet& lights,
                               const ChunkObservations& observations, int harmonics,
                               AccumulationPrecision precision, NormalEquationSums& sums) {
    sums.harmonics = std::clamp(harmonics, 0, kMaxHarmonics);
    // Clear only what this M reads and writes; the arrays are sized for kMaxHarmonics.
    const int m = sums.harmonics;
    const auto clear = [](double(&row)[kLanes]) { std::fill(row, row + kLanes, 0.0); };
    for (int k = 0; k <= 2 * m; ++k) {
        clear(sums.cosine[k]);
        clear(sums.sine[k]);
    }
    for (int k = 0; k <= m; ++k) {
        clear(sums.lambertCosine[k]);
        clear(sums.lambertSine[k]);
    }
    for (int c = 0; c < kChannels; ++c) {
        for (int j = 0; j < proto::coefficientCount(m); ++j) {
            clear(sums.projection[c][j]);
        }
        clear(sums.squares[c]);
    }
    clear(sums.lambertSquare);
    clear(sums.count);
    sums.roundingLevel = precision == AccumulationPrecision::kFloatBlocks ? 1e-7 : 1e-13;
    if (precision == AccumulationPrecision::kFloatBlocks) {
        accumulateFast(geometry, lights, observations, sums.harmonics, sums);
    } else {
        accumulateExact(geometry, lights, observations, sums.harmonics, sums);
    }
}

void assembleNormalMatrix(const NormalEquationSums& sums, int lane, int harmonics, double* matrix) {
    const int k = proto::coefficientCount(harmonics);
    auto get = [lane](const double(&row)[kLanes]) { return row[lane]; };
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
            matrix[i * k + j] = normalMatrixEntry<double>(sums, i, j, get);
        }
    }
}

// Lower triangle, packed row by row: the whole factor of a 22-coefficient model stays in L1.
constexpr int packedIndex(int i, int j) {
    return i * (i + 1) / 2 + j;
}

namespace {

// Solves kHalfLanes lanes from `first` on. Two halves of one zmm of doubles each, not one
// 16-lane pack: the 16-lane form kept two registers per value and spilled most of them, and
// the solve took a quarter of the fit's time.
using HalfPack = simd::Pack<double, kHalfLanes>;

[[gnu::always_inline]] inline void solveLanes(const NormalEquationSums& sums, int harmonics,
                                              double lambda, int first, ChunkSolution& solution) {
    const int k = proto::coefficientCount(harmonics);
    auto get = [first](const double(&row)[kLanes]) __attribute__((always_inline)) {
        return HalfPack::load(row + first);
    };

    HalfPack factor[kMaxCoefficients * (kMaxCoefficients + 1) / 2];
    HalfPack diagonal[kMaxCoefficients];
    HalfPack trace(0.0);
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j <= i; ++j) {
            factor[packedIndex(i, j)] = normalMatrixEntry<HalfPack>(sums, i, j, get);
        }
        trace = trace + factor[packedIndex(i, i)];
    }
    const HalfPack ridge = trace * HalfPack(sums.roundingLevel / k);
    for (int i = 0; i < k; ++i) {
        factor[packedIndex(i, i)] =
            factor[packedIndex(i, i)] + ridge + HalfPack(lambda * proto::smoothnessWeight(i));
        diagonal[i] = factor[packedIndex(i, i)];
    }

    // Left-looking Cholesky. Each dot product is a chain of dependent FMAs, so four rows
    // are reduced together to keep the FMA units busy.
    bool singular[kHalfLanes] = {};
    HalfPack inverseDiagonal[kMaxCoefficients];
    for (int j = 0; j < k; ++j) {
        const HalfPack* rowJ = &factor[packedIndex(j, 0)];
        HalfPack pivot = rowJ[j];
        for (int p = 0; p < j; ++p) {
            pivot = pivot - rowJ[p] * rowJ[p];
        }
        // A pivot that cancels to rounding noise means the samples do not determine this
        // coefficient; substitute 1 to keep the arithmetic finite and mark the lane.
        for (int lane = 0; lane < kHalfLanes; ++lane) {
            if (!(pivot.v[lane] > 1e-11 * std::fabs(diagonal[j][lane]))) {
                singular[lane] = true;
                pivot.v[lane] = 1.0;
            }
        }
        const HalfPack root = sqrt(pivot);
        inverseDiagonal[j] = HalfPack(1.0) / root;
        factor[packedIndex(j, j)] = root;
        int i = j + 1;
        for (; i + 3 < k; i += 4) {
            HalfPack* r0 = &factor[packedIndex(i, 0)];
            HalfPack* r1 = &factor[packedIndex(i + 1, 0)];
            HalfPack* r2 = &factor[packedIndex(i + 2, 0)];
            HalfPack* r3 = &factor[packedIndex(i + 3, 0)];
            HalfPack v0 = r0[j], v1 = r1[j], v2 = r2[j], v3 = r3[j];
            for (int p = 0; p < j; ++p) {
                const HalfPack l = rowJ[p];
                v0 = v0 - r0[p] * l;
                v1 = v1 - r1[p] * l;
                v2 = v2 - r2[p] * l;
                v3 = v3 - r3[p] * l;
            }
            r0[j] = v0 * inverseDiagonal[j];
            r1[j] = v1 * inverseDiagonal[j];
            r2[j] = v2 * inverseDiagonal[j];
            r3[j] = v3 * inverseDiagonal[j];
        }
        for (; i < k; ++i) {
            HalfPack* row = &factor[packedIndex(i, 0)];
            HalfPack value = row[j];
            for (int p = 0; p < j; ++p) {
                value = value - row[p] * rowJ[p];
            }
            row[j] = value * inverseDiagonal[j];
        }
    }

    // Both triangular solves run the three channels side by side (independent chains).
    HalfPack x[kChannels][kMaxCoefficients];
    for (int i = 0; i < k; ++i) {  // L z = b
        const HalfPack* row = &factor[packedIndex(i, 0)];
        HalfPack v[kChannels];
        for (int c = 0; c < kChannels; ++c) {
            v[c] = get(sums.projection[c][i]);
        }
        for (int p = 0; p < i; ++p) {
            for (int c = 0; c < kChannels; ++c) {
                v[c] = v[c] - row[p] * x[c][p];
            }
        }
        for (int c = 0; c < kChannels; ++c) {
            x[c][i] = v[c] * inverseDiagonal[i];
        }
    }
    for (int i = k - 1; i >= 0; --i) {  // Lᵀ x = z
        HalfPack v[kChannels] = {x[0][i], x[1][i], x[2][i]};
        for (int p = i + 1; p < k; ++p) {
            const HalfPack l = factor[packedIndex(p, i)];
            for (int c = 0; c < kChannels; ++c) {
                v[c] = v[c] - l * x[c][p];
            }
        }
        for (int c = 0; c < kChannels; ++c) {
            x[c][i] = v[c] * inverseDiagonal[i];
        }
    }

    for (int lane = 0; lane < kHalfLanes; ++lane) {
        solution.valid[first + lane] = !singular[lane] && sums.count[first + lane] >= k - 0.5;
    }
    for (int c = 0; c < kChannels; ++c) {
        // Residual from the sums: with (G + λR + δI)x = b, Σ r² = Σy² − xᵀb − xᵀ(λR + δI)x.
        HalfPack explained(0.0), penalty(0.0);
        for (int i = 0; i < k; ++i) {
            explained = explained + x[c][i] * get(sums.projection[c][i]);
            penalty = penalty +
                      x[c][i] * x[c][i] * (HalfPack(lambda * proto::smoothnessWeight(i)) + ridge);
        }
        const HalfPack residual = get(sums.squares[c]) - explained - penalty;
        for (int lane = 0; lane < kHalfLanes; ++lane) {
            const bool valid = solution.valid[first + lane];
            // Only the 2M + 2 coefficients of this M are written; readers never look further.
            for (int i = 0; i < k; ++i) {
                solution.coefficients[first + lane][c][i] =
                    valid ? static_cast<float>(x[c][i][lane]) : 0.0f;
            }
            solution.rms[first + lane][c] =
                valid ? static_cast<float>(
                            std::sqrt(std::max(residual[lane], 0.0) / sums.count[first + lane]))
                      : 0.0f;
        }
    }
}

}  // namespace

VPE_KERNEL_CLONES
void solveNormalEquations(const NormalEquationSums& sums, int harmonics, double lambda,
                          ChunkSolution& solution) {
    harmonics = std::min(harmonics, sums.harmonics);
    solveLanes(sums, harmonics, lambda, 0, solution);
    solveLanes(sums, harmonics, lambda, kHalfLanes, solution);
}

}  // namespace vpe::fit
