// SPDX-License-Identifier: MIT
// Normal equations of the Fourier BRDF fit: accumulation (the hot loop, SIMD over pixels)
// and batched Cholesky solve. Written once with Google Highway: this file is compiled again
// for each SIMD target (hwy/foreach_target.h) and the CPU picks one at run time.

// The target-independent part, compiled once.
#ifndef VPE_FIT_NORMAL_EQUATIONS_ONCE
#define VPE_FIT_NORMAL_EQUATIONS_ONCE

#include "vpe/fit/normal_equations.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <new>
#include <string>
#include <type_traits>

#include "vpe/common/input_error.h"
#include "vpe/proto/reflection_geometry.h"

// Scalable vectors (SVE) have no size at compile time and cannot be members of the structs the
// kernels keep their vectors in; arm64 gets NEON.
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128)

namespace vpe::fit {
namespace {

// Samples summed in float before the block is added to the double sums: short enough that
// float rounding stays near 1e-7 relative, long enough to keep the flush cheap.
constexpr int kSampleBlock = 64;
constexpr int kPrefetchDistance = 8;

// Lower triangle, packed row by row: the whole factor of a 22-coefficient model stays in L1.
constexpr int packedIndex(int i, int j) {
    return i * (i + 1) / 2 + j;
}

}  // namespace
}  // namespace vpe::fit

#endif  // VPE_FIT_NORMAL_EQUATIONS_ONCE

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "normal_equations.cpp"
#include <hwy/cache_control.h>
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "pixel_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace vpe::fit::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using proto::cosineIndex;
using proto::kMaxHarmonics;
using proto::sineIndex;

// sum += a·b in one fused multiply-add.
template <class D>
HWY_INLINE void addProduct(PixelLanes<D> a, PixelLanes<D> b, PixelLanes<D>& sum) {
    sum.v = hn::MulAdd(a.v, b.v, sum.v);
}

// Harmonics whose accumulators a sample pass keeps in registers. Ten accumulators a harmonic:
// two harmonics fill half of a 32-register file (AVX-512, NEON) but spill from the 16 of
// AVX2 and SSE4.
#if HWY_ARCH_X86 && HWY_TARGET > HWY_AVX3
constexpr int kHarmonicsPerPass = 1;
#else
constexpr int kHarmonicsPerPass = 2;
#endif

// Observations are stored in float; the exact path widens them to double.
template <class D>
HWY_INLINE PixelLanes<D> loadObservation(D d, const float* p) {
    if constexpr (std::is_same_v<hn::TFromD<D>, float>) {
        return PixelLanes<D>(hn::LoadU(d, p));
    } else {
        return PixelLanes<D>(hn::PromoteTo(d, hn::LoadU(hn::Rebind<float, D>(), p)));
    }
}

// sums[0 .. Lanes(d)) += partial, in double; the partial is cleared.
template <class D>
HWY_INLINE void flushPartial(D d, PixelLanes<D>& partial, double* sums) {
    if constexpr (std::is_same_v<hn::TFromD<D>, double>) {
        hn::StoreU(hn::Add(hn::LoadU(d, sums), partial.v), d, sums);
    } else {
#if HWY_TARGET == HWY_SCALAR  // one lane: no halves
        sums[0] += static_cast<double>(hn::GetLane(partial.v));
#else
        const hn::Half<D> half;
        const hn::Rebind<double, decltype(half)> wide;
        const auto lower = hn::PromoteTo(wide, hn::LowerHalf(half, partial.v));
        const auto upper = hn::PromoteTo(wide, hn::UpperHalf(half, partial.v));
        double* upperSums = sums + hn::Lanes(wide);
        hn::StoreU(hn::Add(hn::LoadU(wide, sums), lower), wide, sums);
        hn::StoreU(hn::Add(hn::LoadU(wide, upperSums), upper), wide, upperSums);
#endif
    }
    partial = PixelLanes<D>(0);
}

template <class P>
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

// What one sample contributes, for the pixels of a slice.
template <class P>
struct SampleTerms {
    P cosThetaS;
    P lambert;                   // max(cos θd, 0)
    P weight;                    // w
    P weightedLambert;           // w·d
    P weightedValue[kChannels];  // w·y
    P value[kChannels];          // y, normalized by the light's irradiance
};

// The pixels [first, first + Lanes(d)) of a chunk: their geometry and where their samples are.
template <class D>
struct Slice {
    using P = PixelLanes<D>;
    D d;
    int first;
    proto::Vec3<P> normal, view, position;
};

template <class D, bool kPointLights>
HWY_INLINE Slice<D> loadSlice(D d, const ChunkGeometry& geometry, int first) {
    using P = PixelLanes<D>;
    const auto load = [&](const float(&row)[kLanes])
                          HWY_ATTR { return loadObservation(d, row + first); };
    Slice<D> slice{d, first, {}, {}, {}};
    slice.normal = {load(geometry.normal[0]), load(geometry.normal[1]), load(geometry.normal[2])};
    slice.view = {load(geometry.view[0]), load(geometry.view[1]), load(geometry.view[2])};
    slice.position = {P(0), P(0), P(0)};
    if constexpr (kPointLights) {
        slice.position = {load(geometry.position[0]), load(geometry.position[1]),
                          load(geometry.position[2])};
    }
    return slice;
}

// Written in place: returned by value, the ten vectors were copied to the block's array with a
// `rep movs` per sample, a tenth of the fit's time on AVX2.
template <class D, bool kPointLights>
HWY_INLINE void sampleTerms(const Slice<D>& slice, const KernelLightSet& lights,
                            const ChunkObservations& observations, int s,
                            SampleTerms<PixelLanes<D>>& terms) {
    using P = PixelLanes<D>;
    const KernelLight& light = lights.lights[s];
    proto::Vec3<P> toLight;
    P scale;
    if constexpr (kPointLights) {
        const P dx = P(light.x) - slice.position.x;
        const P dy = P(light.y) - slice.position.y;
        const P dz = P(light.z) - slice.position.z;
        const P distanceSquared = dx * dx + dy * dy + dz * dz;
        const P inverseDistance = P(1) / sqrt(distanceSquared);
        toLight = {dx * inverseDistance, dy * inverseDistance, dz * inverseDistance};
        scale = distanceSquared * P(light.inverseIntensity / lights.referenceDistanceSquared);
    } else {
        toLight = {P(light.x), P(light.y), P(light.z)};
        scale = P(light.inverseIntensity);
    }
    const proto::ReflectionAngles<P> angles =
        proto::reflectionAngles(slice.normal, toLight, slice.view);
    terms.cosThetaS = angles.cosThetaS;
    terms.lambert = proto::lambertBasis(angles.cosThetaD);
    terms.weight = observations.weights
                       ? loadObservation(slice.d, observations.weights +
                                                      s * observations.weightStride + slice.first)
                       : P(1);
    terms.weightedLambert = terms.weight * terms.lambert;
    const float* values = observations.values + s * observations.sampleStride + slice.first;
    for (int c = 0; c < kChannels; ++c) {
        terms.value[c] = loadObservation(slice.d, values + c * observations.channelStride) * scale;
        terms.weightedValue[c] = terms.weight * terms.value[c];
    }
}

// Harmonics m0 .. m0 + G − 1 over one block of samples, with their accumulators held in
// registers: each sample's recurrence state is loaded, advanced G steps and stored back, so
// memory traffic is per group of harmonics, not per accumulator update. `full` adds the
// Lambert and projection sums (harmonics ≤ M); beyond M only the plain sums continue.
template <int G, bool kFull, class P>
HWY_INLINE void accumulateHarmonicGroup(const SampleTerms<P>* terms,
                                        proto::HarmonicRecurrence<P>* state, int count, int m0,
                                        Partials<P>& p) {
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
            addProduct(t.weight, c, acc[j][0]);
            addProduct(t.weight, sn, acc[j][1]);
            if constexpr (kFull) {
                addProduct(t.weightedLambert, c, acc[j][2]);
                addProduct(t.weightedLambert, sn, acc[j][3]);
                for (int k = 0; k < kChannels; ++k) {
                    addProduct(t.weightedValue[k], c, acc[j][4 + 2 * k]);
                    addProduct(t.weightedValue[k], sn, acc[j][5 + 2 * k]);
                }
            }
        }
    }
    for (int j = 0; j < G; ++j) {
        const int m = m0 + j;
        p.cosine[m] = p.cosine[m] + acc[j][0];
        p.sine[m] = p.sine[m] + acc[j][1];
        if constexpr (kFull) {
            p.lambertCosine[m] = p.lambertCosine[m] + acc[j][2];
            p.lambertSine[m] = p.lambertSine[m] + acc[j][3];
            for (int k = 0; k < kChannels; ++k) {
                P& cosineSum = p.projection[k][cosineIndex(m)];
                P& sineSum = p.projection[k][sineIndex(m)];
                cosineSum = cosineSum + acc[j][4 + 2 * k];
                sineSum = sineSum + acc[j][5 + 2 * k];
            }
        }
    }
}

// Adds the samples [begin, begin + count) of one slice's pixels to the sums.
template <class D, bool kPointLights>
HWY_INLINE void accumulateBlock(const Slice<D>& slice, const KernelLightSet& lights,
                                const ChunkObservations& observations, int harmonics, int begin,
                                int count, Partials<PixelLanes<D>>& partial,
                                SampleTerms<PixelLanes<D>>* terms,
                                proto::HarmonicRecurrence<PixelLanes<D>>* state,
                                NormalEquationSums& sums) {
    using P = PixelLanes<D>;
    const int coefficients = proto::coefficientCount(harmonics);
    const int gramHarmonics = 2 * harmonics;
    for (int i = 0; i < count; ++i) {
        // The band streams from memory at ~5 GB/s; ask for samples a few ahead.
        const int ahead = begin + i + kPrefetchDistance;
        if (ahead < lights.count) {
            const float* next =
                observations.values + ahead * observations.sampleStride + slice.first;
            for (int c = 0; c < kChannels; ++c) {
                hwy::Prefetch(next + c * observations.channelStride);
            }
            if (observations.weights) {
                hwy::Prefetch(observations.weights + ahead * observations.weightStride +
                              slice.first);
            }
        }
        sampleTerms<D, kPointLights>(slice, lights, observations, begin + i, terms[i]);
        new (&state[i]) proto::HarmonicRecurrence<P>(terms[i].cosThetaS);
        const SampleTerms<P>& t = terms[i];
        partial.count = partial.count + t.weight;
        partial.cosine[0] = partial.cosine[0] + t.weight;
        addProduct(t.weightedLambert, t.lambert, partial.lambertSquare);
        partial.lambertCosine[0] = partial.lambertCosine[0] + t.weightedLambert;
        for (int c = 0; c < kChannels; ++c) {
            addProduct(t.weightedValue[c], t.value[c], partial.squares[c]);
            addProduct(t.weightedValue[c], t.lambert, partial.projection[c][proto::kLambertIndex]);
            addProduct(t.weightedValue[c], P(proto::kConstantBasis),
                       partial.projection[c][proto::kConstantIndex]);
        }
    }
    int m = 1;
    for (; m + kHarmonicsPerPass - 1 <= harmonics; m += kHarmonicsPerPass) {
        accumulateHarmonicGroup<kHarmonicsPerPass, true>(terms, state, count, m, partial);
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

    const D d = slice.d;
    const int first = slice.first;
    for (int k = 0; k <= gramHarmonics; ++k) {
        flushPartial(d, partial.cosine[k], sums.cosine[k] + first);
        flushPartial(d, partial.sine[k], sums.sine[k] + first);
    }
    for (int k = 0; k <= harmonics; ++k) {
        flushPartial(d, partial.lambertCosine[k], sums.lambertCosine[k] + first);
        flushPartial(d, partial.lambertSine[k], sums.lambertSine[k] + first);
    }
    flushPartial(d, partial.lambertSquare, sums.lambertSquare + first);
    for (int c = 0; c < kChannels; ++c) {
        for (int j = 0; j < coefficients; ++j) {
            flushPartial(d, partial.projection[c][j], sums.projection[c][j] + first);
        }
        flushPartial(d, partial.squares[c], sums.squares[c] + first);
    }
    flushPartial(d, partial.count, sums.count + first);
}

// The chunk's kLanes pixels in slices of Lanes(d): one vector per value, never a pair of
// registers (as 8-lane vectors on AVX2 the loops spilled them to the stack). Each block of
// samples is read by every slice while it is in L1.
template <class D, bool kPointLights>
HWY_INLINE void accumulateChunk(D d, const ChunkGeometry& geometry, const KernelLightSet& lights,
                                const ChunkObservations& observations, int harmonics,
                                NormalEquationSums& sums) {
    using P = PixelLanes<D>;
    static_assert(kLanes % hn::MaxLanes(D()) == 0, "a chunk is a whole number of slices");
    const int sliceLanes = static_cast<int>(hn::Lanes(d));
    // Only the rows this M uses are cleared (the arrays are sized for kMaxHarmonics); flushing
    // clears them again after each block.
    Partials<P> partial;
    for (int k = 0; k <= 2 * harmonics; ++k) {
        partial.cosine[k] = P(0);
        partial.sine[k] = P(0);
    }
    for (int k = 0; k <= harmonics; ++k) {
        partial.lambertCosine[k] = P(0);
        partial.lambertSine[k] = P(0);
    }
    for (int c = 0; c < kChannels; ++c) {
        for (int j = 0; j < proto::coefficientCount(harmonics); ++j) {
            partial.projection[c][j] = P(0);
        }
        partial.squares[c] = P(0);
    }
    partial.lambertSquare = P(0);
    partial.count = P(0);
    SampleTerms<P> terms[kSampleBlock];
    alignas(64) unsigned char stateStorage[kSampleBlock * sizeof(proto::HarmonicRecurrence<P>)];
    auto* state = reinterpret_cast<proto::HarmonicRecurrence<P>*>(stateStorage);
    for (int begin = 0; begin < lights.count; begin += kSampleBlock) {
        const int count = std::min(lights.count - begin, kSampleBlock);
        for (int first = 0; first < kLanes; first += sliceLanes) {
            const Slice<D> slice = loadSlice<D, kPointLights>(d, geometry, first);
            accumulateBlock<D, kPointLights>(slice, lights, observations, harmonics, begin, count,
                                             partial, terms, state, sums);
        }
    }
}

HWY_FLATTEN void accumulateInFloatBlocks(const ChunkGeometry& geometry,
                                         const KernelLightSet& lights,
                                         const ChunkObservations& observations, int harmonics,
                                         NormalEquationSums& sums) {
    using D = hn::ScalableTag<float>;
    if (lights.point) {
        accumulateChunk<D, true>(D(), geometry, lights, observations, harmonics, sums);
    } else {
        accumulateChunk<D, false>(D(), geometry, lights, observations, harmonics, sums);
    }
}

HWY_FLATTEN void accumulateInDouble(const ChunkGeometry& geometry, const KernelLightSet& lights,
                                    const ChunkObservations& observations, int harmonics,
                                    NormalEquationSums& sums) {
    using D = hn::ScalableTag<double>;
    if (lights.point) {
        accumulateChunk<D, true>(D(), geometry, lights, observations, harmonics, sums);
    } else {
        accumulateChunk<D, false>(D(), geometry, lights, observations, harmonics, sums);
    }
}

// One entry of the normal matrix from the sums (product-to-sum identities), for T = double
// (one lane) or PixelLanes (a slice); get(row) reads a [kLanes] row of the sums.
template <typename T, typename Get>
HWY_INLINE T normalMatrixEntry(const NormalEquationSums& sums, int i, int j, Get get) {
    if (i > j) {
        std::swap(i, j);
    }
    constexpr double kHalf = 0.5;
    const T r2 = T(proto::kConstantBasis);
    auto cosSum = [&](int k) HWY_ATTR { return get(sums.cosine[k < 0 ? -k : k]); };
    auto sinSum = [&](int k) HWY_ATTR {
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

HWY_FLATTEN void assembleLaneMatrix(const NormalEquationSums& sums, int lane, int harmonics,
                                    double* matrix) {
    const int k = proto::coefficientCount(harmonics);
    auto get = [lane](const double(&row)[kLanes]) { return row[lane]; };
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
            matrix[i * k + j] = normalMatrixEntry<double>(sums, i, j, get);
        }
    }
}

// Solves the pixels [first, first + Lanes(d)) of the chunk: one vector of doubles per value.
template <class D>
HWY_INLINE void solveSlice(D d, const NormalEquationSums& sums, int harmonics, double lambda,
                           int first, ChunkSolution& solution) {
    using P = PixelLanes<D>;
    const int sliceLanes = static_cast<int>(hn::Lanes(d));
    const int k = proto::coefficientCount(harmonics);
    auto get = [d, first](const double(&row)[kLanes])
                   HWY_ATTR { return P(hn::LoadU(d, row + first)); };

    P factor[kMaxCoefficients * (kMaxCoefficients + 1) / 2];
    P diagonal[kMaxCoefficients];
    P trace(0.0);
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j <= i; ++j) {
            factor[packedIndex(i, j)] = normalMatrixEntry<P>(sums, i, j, get);
        }
        trace = trace + factor[packedIndex(i, i)];
    }
    const P ridge = trace * P(sums.roundingLevel / k);
    for (int i = 0; i < k; ++i) {
        factor[packedIndex(i, i)] =
            factor[packedIndex(i, i)] + ridge + P(lambda * proto::smoothnessWeight(i));
        diagonal[i] = factor[packedIndex(i, i)];
    }

    // Left-looking Cholesky. Each dot product is a chain of dependent FMAs, so four rows
    // are reduced together to keep the FMA units busy.
    auto singular = hn::FirstN(d, 0);
    P inverseDiagonal[kMaxCoefficients];
    for (int j = 0; j < k; ++j) {
        const P* rowJ = &factor[packedIndex(j, 0)];
        P pivot = rowJ[j];
        for (int p = 0; p < j; ++p) {
            pivot = pivot - rowJ[p] * rowJ[p];
        }
        // A pivot that cancels to rounding noise (or is NaN) means the samples do not determine
        // this coefficient; substitute 1 to keep the arithmetic finite and mark the lane.
        const auto undetermined =
            hn::Not(hn::Gt(pivot.v, hn::Mul(hn::Set(d, 1e-11), hn::Abs(diagonal[j].v))));
        singular = hn::Or(singular, undetermined);
        pivot = P(hn::IfThenElse(undetermined, hn::Set(d, 1.0), pivot.v));
        const P root = sqrt(pivot);
        inverseDiagonal[j] = P(1.0) / root;
        factor[packedIndex(j, j)] = root;
        int i = j + 1;
        for (; i + 3 < k; i += 4) {
            P* r0 = &factor[packedIndex(i, 0)];
            P* r1 = &factor[packedIndex(i + 1, 0)];
            P* r2 = &factor[packedIndex(i + 2, 0)];
            P* r3 = &factor[packedIndex(i + 3, 0)];
            P v0 = r0[j], v1 = r1[j], v2 = r2[j], v3 = r3[j];
            for (int p = 0; p < j; ++p) {
                const P l = rowJ[p];
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
            P* row = &factor[packedIndex(i, 0)];
            P value = row[j];
            for (int p = 0; p < j; ++p) {
                value = value - row[p] * rowJ[p];
            }
            row[j] = value * inverseDiagonal[j];
        }
    }

    // Both triangular solves run the three channels side by side (independent chains).
    P x[kChannels][kMaxCoefficients];
    for (int i = 0; i < k; ++i) {  // L z = b
        const P* row = &factor[packedIndex(i, 0)];
        P v[kChannels];
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
        P v[kChannels] = {x[0][i], x[1][i], x[2][i]};
        for (int p = i + 1; p < k; ++p) {
            const P l = factor[packedIndex(p, i)];
            for (int c = 0; c < kChannels; ++c) {
                v[c] = v[c] - l * x[c][p];
            }
        }
        for (int c = 0; c < kChannels; ++c) {
            x[c][i] = v[c] * inverseDiagonal[i];
        }
    }

    // The lanes' values, one slice of the chunk at a time, for the per-pixel outputs.
    HWY_ALIGN double lanes[kLanes];
    hn::StoreU(hn::VecFromMask(d, singular), d, lanes);
    for (int lane = 0; lane < sliceLanes; ++lane) {
        solution.valid[first + lane] = lanes[lane] == 0.0 && sums.count[first + lane] >= k - 0.5;
    }
    for (int c = 0; c < kChannels; ++c) {
        for (int i = 0; i < k; ++i) {
            hn::StoreU(x[c][i].v, d, lanes);
            for (int lane = 0; lane < sliceLanes; ++lane) {
                // Only the 2M + 2 coefficients of this M are written; readers never look
                // further.
                solution.coefficients[first + lane][c][i] =
                    solution.valid[first + lane] ? static_cast<float>(lanes[lane]) : 0.0f;
            }
        }
        // Residual from the sums: with (G + λR + δI)x = b, Σ r² = Σy² − xᵀb − xᵀ(λR + δI)x.
        P explained(0.0), penalty(0.0);
        for (int i = 0; i < k; ++i) {
            explained = explained + x[c][i] * get(sums.projection[c][i]);
            penalty =
                penalty + x[c][i] * x[c][i] * (P(lambda * proto::smoothnessWeight(i)) + ridge);
        }
        const P residual = get(sums.squares[c]) - explained - penalty;
        hn::StoreU(residual.v, d, lanes);
        for (int lane = 0; lane < sliceLanes; ++lane) {
            solution.rms[first + lane][c] =
                solution.valid[first + lane]
                    ? static_cast<float>(
                          std::sqrt(std::max(lanes[lane], 0.0) / sums.count[first + lane]))
                    : 0.0f;
        }
    }
}

HWY_FLATTEN void solveChunk(const NormalEquationSums& sums, int harmonics, double lambda,
                            ChunkSolution& solution) {
    using D = hn::ScalableTag<double>;
    const D d;
    static_assert(kLanes % hn::MaxLanes(D()) == 0, "a chunk is a whole number of slices");
    for (int first = 0; first < kLanes; first += static_cast<int>(hn::Lanes(d))) {
        solveSlice(d, sums, harmonics, lambda, first, solution);
    }
}

std::int64_t compiledTarget() {
    return HWY_TARGET;
}

}  // namespace vpe::fit::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

namespace vpe::fit {

HWY_EXPORT(accumulateInFloatBlocks);
HWY_EXPORT(accumulateInDouble);
HWY_EXPORT(assembleLaneMatrix);
HWY_EXPORT(solveChunk);
HWY_EXPORT(compiledTarget);

void accumulateNormalEquations(const ChunkGeometry& geometry, const KernelLightSet& lights,
                               const ChunkObservations& observations, int harmonics,
                               AccumulationPrecision precision, NormalEquationSums& sums) {
    sums.harmonics = std::clamp(harmonics, 0, proto::kMaxHarmonics);
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
        HWY_DYNAMIC_DISPATCH(accumulateInFloatBlocks)(geometry, lights, observations, m, sums);
    } else {
        HWY_DYNAMIC_DISPATCH(accumulateInDouble)(geometry, lights, observations, m, sums);
    }
}

void assembleNormalMatrix(const NormalEquationSums& sums, int lane, int harmonics, double* matrix) {
    HWY_DYNAMIC_DISPATCH(assembleLaneMatrix)(sums, lane, harmonics, matrix);
}

void solveNormalEquations(const NormalEquationSums& sums, int harmonics, double lambda,
                          ChunkSolution& solution) {
    HWY_DYNAMIC_DISPATCH(solveChunk)(sums, std::min(harmonics, sums.harmonics), lambda, solution);
}

std::vector<std::int64_t> kernelTargets() {
    return hwy::SupportedAndGeneratedTargets();
}

std::int64_t activeKernelTarget() {
    return HWY_DYNAMIC_DISPATCH(compiledTarget)();
}

const char* kernelTargetName(std::int64_t target) {
    // Highway's portable fallback is SCALAR with GCC and EMU128 (128-bit vectors emulated in
    // plain C++) with clang: to a user both are the code without a vector unit.
    return target == HWY_SCALAR || target == HWY_EMU128 ? "SCALAR" : hwy::TargetName(target);
}

const char* activeKernelTargetName() {
    return kernelTargetName(activeKernelTarget());
}

void restrictKernelTarget(std::string_view name) {
    const auto sameName = [name](std::string_view target) {
        return std::equal(name.begin(), name.end(), target.begin(), target.end(),
                          [](char a, char b) {
                              return std::toupper(static_cast<unsigned char>(a)) ==
                                     std::toupper(static_cast<unsigned char>(b));
                          });
    };
    std::string choices;
    for (const std::int64_t target : kernelTargets()) {
        if (sameName(kernelTargetName(target))) {
            // Every better target off: the dispatch then picks this one.
            hwy::DisableTargets(target - 1);
            return;
        }
        choices += (choices.empty() ? "" : ", ") + std::string(kernelTargetName(target));
    }
    throw common::InputError("VPE_SIMD=" + std::string(name) +
                             ": not a SIMD target this build and CPU run (" + choices + ")");
}

}  // namespace vpe::fit

#endif  // HWY_ONCE
