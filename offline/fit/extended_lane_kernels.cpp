// SPDX-License-Identifier: MIT
// The extended fit's lane kernels (extended_lane_kernels.h): f's predictions and training
// error, T's normal equations, ridge solves and PRESS, every lane of a chunk at once. Written
// once with Google Highway: this file is compiled again for each SIMD target
// (hwy/foreach_target.h) and the CPU picks one at run time.

// The target-independent part, compiled once.
#ifndef VPE_FIT_EXTENDED_LANE_KERNELS_ONCE
#define VPE_FIT_EXTENDED_LANE_KERNELS_ONCE

#include "vpe/fit/extended_lane_kernels.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/luminance.h"

// As in normal_equations.cpp: the kernels keep vectors in structs, which scalable vectors
// (SVE) cannot be; arm64 gets NEON.
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128)

namespace vpe::fit {
namespace {

constexpr int kTransportTerms = model::kTransportTerms;
constexpr int kTransportPairs = ExtendedLightTable::kTransportPairs;

// Where entry (row, column) of a symmetric T matrix sits in the packed layout (the upper
// triangle, row by row), either way round.
constexpr int transportPair(int row, int column) {
    if (row > column) {
        std::swap(row, column);
    }
    return row * kTransportTerms - row * (row - 1) / 2 + (column - row);
}

// Where lane `first` of entry `entry` of an [entry][lane] array is.
constexpr std::size_t laneAt(std::size_t entry, int first) {
    return entry * kLanes + static_cast<std::size_t>(first);
}

}  // namespace
}  // namespace vpe::fit

#endif  // VPE_FIT_EXTENDED_LANE_KERNELS_ONCE

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "extended_lane_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "pixel_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace vpe::fit::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

// The kernels take a chunk's lanes a slice at a time: one vector of doubles (8 lanes on
// AVX-512, 4 on AVX2, 2 on SSE4 and NEON), lanes first … first + Lanes(d) − 1. As one 8-lane
// GCC vector on every target, an AVX2 machine kept each value in two registers and spilled.
using D = hn::ScalableTag<double>;
using P = PixelLanes<D>;
static_assert(kLanes % hn::MaxLanes(D()) == 0, "a chunk is a whole number of slices");

HWY_INLINE int sliceLanes() {
    return static_cast<int>(hn::Lanes(D()));
}

HWY_INLINE P load(const double* p) {
    return P(hn::LoadU(D(), p));
}

HWY_INLINE P loadFloats(const float* p) {
    return P(hn::PromoteTo(D(), hn::LoadU(hn::Rebind<float, D>(), p)));
}

// A slice's BRDF coefficients, each across its lanes: [channel][coefficient], up to M's.
using LaneCoefficients = P[kChannels][kMaxCoefficients];
HWY_INLINE void laneCoefficients(const ChunkSolution& brdf, int harmonics, int first,
                                 LaneCoefficients& out) {
    HWY_ALIGN double lanes[kLanes];
    for (int c = 0; c < kChannels; ++c) {
        for (int k = 0; k < proto::coefficientCount(harmonics); ++k) {
            for (int lane = 0; lane < sliceLanes(); ++lane) {
                lanes[lane] = static_cast<double>(brdf.coefficients[first + lane][c][k]);
            }
            out[c][k] = P(hn::Load(D(), lanes));
        }
    }
}

// f of sample s for a slice's lanes, per channel. Flattened itself, not only inlined into the
// flattened kernels: there GCC left proto's evaluateFourierBrdfRgb out of line (its size limit),
// compiled outside the target's region, and an AVX-512 vector passed to it by value was garbage.
HWY_FLATTEN void evaluateLanes(const LaneCoefficients& coefficients, int harmonics,
                               const LaneSamples& samples, int s, int first, P (&rgb)[3]) {
    const std::size_t i = laneAt(static_cast<std::size_t>(s), first);
    proto::evaluateFourierBrdfRgb(&coefficients[0][0], kMaxCoefficients, harmonics,
                                  load(samples.cosD + i), load(samples.cosS + i), rgb);
}

HWY_FLATTEN void predictEveryLaneKernel(const ChunkSolution& brdf, int harmonics,
                                        const LaneSamples& samples, double* rgbOut,
                                        double* luminanceOut) {
    for (int first = 0; first < kLanes; first += sliceLanes()) {
        LaneCoefficients coefficients;
        laneCoefficients(brdf, harmonics, first, coefficients);
        for (int s = 0; s < samples.count; ++s) {
            const std::size_t i = laneAt(static_cast<std::size_t>(s), first);
            P rgb[3];
            evaluateLanes(coefficients, harmonics, samples, s, first, rgb);
            const P irradiance = load(samples.irradiance + i);
            for (int c = 0; c < 3; ++c) {
                rgb[c] = irradiance * rgb[c];
                hn::StoreU(rgb[c].v, D(),
                           rgbOut + laneAt(static_cast<std::size_t>(s) * 3 + c, first));
            }
            const P luminance = P(proto::kLuminance709[0]) * rgb[0] +
                                P(proto::kLuminance709[1]) * rgb[1] +
                                P(proto::kLuminance709[2]) * rgb[2];
            hn::StoreU(luminance.v, D(), luminanceOut + i);
        }
    }
}

HWY_FLATTEN void everyLaneErrorKernel(const ChunkSolution& brdf, int harmonics,
                                      const LaneSamples& samples, const LaneObservations& observed,
                                      double* error) {
    const D d;
    const hn::Rebind<std::uint8_t, D> bytes;
    const hn::Rebind<std::int32_t, D> words;
    const auto zero = hn::Zero(d);
    for (int first = 0; first < kLanes; first += sliceLanes()) {
        LaneCoefficients coefficients;
        laneCoefficients(brdf, harmonics, first, coefficients);
        auto sum = hn::Zero(d);
        for (int s = 0; s < samples.count; ++s) {
            const std::size_t i = laneAt(static_cast<std::size_t>(s), first);
            P predicted[3];
            evaluateLanes(coefficients, harmonics, samples, s, first, predicted);
            const P irradiance = load(samples.irradiance + i);
            const auto weight = loadFloats(observed.weights + i).v;
            const auto saturated =
                hn::PromoteTo(d, hn::PromoteTo(words, hn::LoadU(bytes, observed.saturated + i)));
            const auto unweighted = hn::Le(weight, zero);
            const auto clipped = hn::Gt(saturated, zero);
            for (int c = 0; c < 3; ++c) {
                const std::size_t v = laneAt(static_cast<std::size_t>(s) * 3 + c, first);
                const P transport = loadFloats(observed.transport + v);
                const P value = loadFloats(observed.values + v);
                const P model = transport * irradiance * predicted[c];
                const P difference = value - model;
                const auto unused = hn::Or(unweighted, hn::And(clipped, hn::Ge(model.v, value.v)));
                const P term = P(weight) * difference * difference;
                sum = hn::Add(sum, hn::IfThenZeroElse(unused, term.v));
            }
        }
        hn::StoreU(sum, d, error + first);
    }
}

// Entries `entry` … entry + 7 of a slice's Σ_s weight[s][channel] row_s (rows of `rowLength`
// values, one per sample), eight sums in registers: a lane's own loop over its samples spent its
// time loading and storing its 136 sums, and a matrix product (Eigen's) its time packing them.
HWY_INLINE void sumEightEntries(const double* rows, int rowLength, const double* weights,
                                int samples, int channels, int channel, int first, int entry,
                                double* out) {
    const D d;
    constexpr int kEntries = 8;
    hn::Vec<D> sum[kEntries];
    for (int e = 0; e < kEntries; ++e) {
        sum[e] = hn::Zero(d);
    }
    for (int s = 0; s < samples; ++s) {
        const auto weight =
            hn::LoadU(d, weights + laneAt(static_cast<std::size_t>(s) * channels + channel, first));
        const double* row = rows + static_cast<std::size_t>(s) * rowLength + entry;
        for (int e = 0; e < kEntries; ++e) {
            sum[e] = hn::MulAdd(weight, hn::Set(d, row[e]), sum[e]);
        }
    }
    for (int e = 0; e < kEntries; ++e) {
        hn::StoreU(sum[e], d, out + laneAt(static_cast<std::size_t>(entry + e), first));
    }
}

HWY_FLATTEN void sumTransportEquationsKernel(const ExtendedLightTable& table, int samples,
                                             int channels, const double* u, const double* v,
                                             double* pairs, double* rights) {
    static_assert(kTransportPairs % 8 == 0 && kTransportTerms % 8 == 0);
    const double* outer = table.transportOuter.front().data();  // [sample][pair], contiguous
    const double* basis = table.transportBasis.front().data();  // [sample][term]
    for (int c = 0; c < channels; ++c) {
        for (int first = 0; first < kLanes; first += sliceLanes()) {
            for (int k = 0; k < kTransportPairs; k += 8) {
                sumEightEntries(outer, kTransportPairs, u, samples, channels, c, first, k,
                                pairs + static_cast<std::size_t>(c) * kTransportPairs * kLanes);
            }
            for (int t = 0; t < kTransportTerms; t += 8) {
                sumEightEntries(basis, kTransportTerms, v, samples, channels, c, first, t,
                                rights + static_cast<std::size_t>(c) * kTransportTerms * kLanes);
            }
        }
    }
}

// A slice's Cholesky factors of A + pull I, A the packed sums of sumTransportEquations: L(i, j),
// i ≥ j, at transportPair(j, i), and 1 / L(j, j). `positive` is false in a lane whose pivot is
// not positive (no ridge, degenerate lights).
struct LaneCholesky {
    hn::Vec<D> lower[kTransportPairs];
    hn::Vec<D> inverseDiagonal[kTransportTerms];
    hn::Mask<D> positive;
};

HWY_INLINE void factorLanes(const double* pairs, int first, hn::Vec<D> pull, LaneCholesky& out) {
    const D d;
    const auto at = [pairs, first](int entry) HWY_ATTR {
        return hn::LoadU(D(), pairs + laneAt(static_cast<std::size_t>(entry), first));
    };
    out.positive = hn::FirstN(d, kLanes);
    for (int j = 0; j < kTransportTerms; ++j) {
        auto pivot = hn::Add(at(transportPair(j, j)), pull);
        for (int k = 0; k < j; ++k) {
            const auto l = out.lower[transportPair(k, j)];
            pivot = hn::NegMulAdd(l, l, pivot);
        }
        out.positive = hn::And(out.positive, hn::Gt(pivot, hn::Zero(d)));
        const auto diagonal = hn::Sqrt(pivot);
        out.lower[transportPair(j, j)] = diagonal;
        out.inverseDiagonal[j] = hn::Div(hn::Set(d, 1.0), diagonal);
        for (int i = j + 1; i < kTransportTerms; ++i) {
            auto entry = at(transportPair(j, i));
            for (int k = 0; k < j; ++k) {
                entry = hn::NegMulAdd(out.lower[transportPair(k, i)],
                                      out.lower[transportPair(k, j)], entry);
            }
            out.lower[transportPair(j, i)] = hn::Mul(entry, out.inverseDiagonal[j]);
        }
    }
}

// L x = y in place.
HWY_INLINE void forwardLanes(const LaneCholesky& factor, hn::Vec<D> (&x)[kTransportTerms]) {
    for (int i = 0; i < kTransportTerms; ++i) {
        auto y = x[i];
        for (int k = 0; k < i; ++k) {
            y = hn::NegMulAdd(factor.lower[transportPair(k, i)], x[k], y);
        }
        x[i] = hn::Mul(y, factor.inverseDiagonal[i]);
    }
}

// (A + pull I) t = b + pull · prior, from L: L y = right, then Lᵀ t = y.
HWY_INLINE void solveLanes(const LaneCholesky& factor, const double* rights, int first,
                           hn::Vec<D> pull, const double* prior, hn::Vec<D> (&t)[kTransportTerms]) {
    const D d;
    for (int i = 0; i < kTransportTerms; ++i) {
        const std::size_t at = laneAt(static_cast<std::size_t>(i), first);
        t[i] = hn::MulAdd(pull, hn::LoadU(d, prior + at), hn::LoadU(d, rights + at));
    }
    forwardLanes(factor, t);
    for (int i = kTransportTerms - 1; i >= 0; --i) {
        auto y = t[i];
        for (int k = i + 1; k < kTransportTerms; ++k) {
            y = hn::NegMulAdd(factor.lower[transportPair(i, k)], t[k], y);
        }
        t[i] = hn::Mul(y, factor.inverseDiagonal[i]);
    }
}

// Whether each lane of a mask is set, into flags[first …].
HWY_INLINE void storeMask(hn::Mask<D> mask, int first, bool* flags) {
    HWY_ALIGN double lanes[kLanes];
    hn::Store(hn::VecFromMask(D(), mask), D(), lanes);
    for (int lane = 0; lane < sliceLanes(); ++lane) {
        flags[first + lane] = lanes[lane] != 0.0;
    }
}

HWY_FLATTEN void solveTransportLanesKernel(const double* pairs, const double* rights,
                                           const double* pull, const double* prior, double* t,
                                           bool* solved) {
    const D d;
    for (int first = 0; first < kLanes; first += sliceLanes()) {
        const auto ridge = hn::LoadU(d, pull + first);
        LaneCholesky factor;
        factorLanes(pairs, first, ridge, factor);
        hn::Vec<D> x[kTransportTerms];
        solveLanes(factor, rights, first, ridge, prior, x);
        for (int i = 0; i < kTransportTerms; ++i) {
            hn::StoreU(x[i], d, t + laneAt(static_cast<std::size_t>(i), first));
        }
        storeMask(factor.positive, first, solved);
    }
}

HWY_FLATTEN void transportPressLanesKernel(const ExtendedLightTable& table, const double* pairs,
                                           const double* rights, const double* pull,
                                           const double* prior, const LanePressSamples& samples,
                                           double* press, bool* valid) {
    const D d;
    for (int first = 0; first < kLanes; first += sliceLanes()) {
        const auto ridge = hn::LoadU(d, pull + first);
        LaneCholesky factor;
        factorLanes(pairs, first, ridge, factor);
        hn::Vec<D> t[kTransportTerms];
        solveLanes(factor, rights, first, ridge, prior, t);
        auto sum = hn::Zero(d);
        for (int s = 0; s < samples.count; ++s) {
            const double* h = table.transportBasis[static_cast<std::size_t>(s)].data();
            hn::Vec<D> z[kTransportTerms];
            auto fitted = hn::Zero(d);
            for (int k = 0; k < kTransportTerms; ++k) {
                z[k] = hn::Set(d, h[k]);
                fitted = hn::MulAdd(t[k], z[k], fitted);
            }
            forwardLanes(factor, z);
            auto quadratic = hn::Zero(d);
            for (int k = 0; k < kTransportTerms; ++k) {
                quadratic = hn::MulAdd(z[k], z[k], quadratic);
            }
            const std::size_t i = laneAt(static_cast<std::size_t>(s), first);
            const auto weight = hn::LoadU(d, samples.weight + i);
            const auto predicted = hn::LoadU(d, samples.predicted + i);
            const auto leverage =
                hn::Mul(hn::Mul(hn::Mul(weight, predicted), predicted), quadratic);
            const auto residual =
                hn::Div(hn::NegMulAdd(predicted, fitted, hn::LoadU(d, samples.observed + i)),
                        hn::Max(hn::Set(d, 1e-3), hn::Sub(hn::Set(d, 1.0), leverage)));
            const auto term = hn::Mul(hn::Mul(weight, residual), residual);
            sum = hn::Add(sum, hn::IfThenElseZero(hn::Gt(weight, hn::Zero(d)), term));
        }
        auto finite = factor.positive;
        for (int k = 0; k < kTransportTerms; ++k) {
            finite = hn::And(finite, hn::IsFinite(t[k]));
        }
        storeMask(finite, first, valid);
        hn::StoreU(sum, d, press + first);
    }
}

HWY_FLATTEN void sampleTransportLanesKernel(const ExtendedLightTable& table, const double* t,
                                            int samples, float* out) {
    const D d;
    const hn::Rebind<float, D> narrow;
    for (int first = 0; first < kLanes; first += sliceLanes()) {
        hn::Vec<D> coefficients[kTransportTerms];  // in registers for every sample
        for (int k = 0; k < kTransportTerms; ++k) {
            coefficients[k] = hn::LoadU(d, t + laneAt(static_cast<std::size_t>(k), first));
        }
        for (int s = 0; s < samples; ++s) {
            const double* h = table.transportBasis[static_cast<std::size_t>(s)].data();
            auto sum = hn::Zero(d);
            for (int k = 0; k < kTransportTerms; ++k) {
                sum = hn::MulAdd(coefficients[k], hn::Set(d, h[k]), sum);
            }
            const auto bounded = hn::Min(hn::Max(sum, hn::Zero(d)), hn::Set(d, 4.0));
            hn::StoreU(hn::DemoteTo(narrow, bounded), narrow,
                       out + laneAt(static_cast<std::size_t>(s), first));
        }
    }
}

}  // namespace vpe::fit::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

namespace vpe::fit {

HWY_EXPORT(predictEveryLaneKernel);
HWY_EXPORT(everyLaneErrorKernel);
HWY_EXPORT(sumTransportEquationsKernel);
HWY_EXPORT(solveTransportLanesKernel);
HWY_EXPORT(transportPressLanesKernel);
HWY_EXPORT(sampleTransportLanesKernel);

void predictEveryLane(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                      double* rgbOut, double* luminanceOut) {
    HWY_DYNAMIC_DISPATCH(predictEveryLaneKernel)(brdf, harmonics, samples, rgbOut, luminanceOut);
}

void everyLaneError(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                    const LaneObservations& observed, double (&error)[kLanes]) {
    HWY_DYNAMIC_DISPATCH(everyLaneErrorKernel)(brdf, harmonics, samples, observed, error);
}

void sumTransportEquations(const ExtendedLightTable& table, int samples, int channels,
                           const double* u, const double* v, double* pairs, double* rights) {
    if (samples == 0) {
        std::fill_n(pairs, channels * kTransportPairs * kLanes, 0.0);
        std::fill_n(rights, channels * kTransportTerms * kLanes, 0.0);
        return;
    }
    HWY_DYNAMIC_DISPATCH(sumTransportEquationsKernel)
    (table, samples, channels, u, v, pairs, rights);
}

void solveTransportLanes(const double* pairs, const double* rights, const double* pull,
                         const double* prior, double* t, bool (&solved)[kLanes]) {
    HWY_DYNAMIC_DISPATCH(solveTransportLanesKernel)(pairs, rights, pull, prior, t, solved);
}

void transportPressLanes(const ExtendedLightTable& table, const double* pairs, const double* rights,
                         const double* pull, const double* prior, const LanePressSamples& samples,
                         double (&press)[kLanes], bool (&valid)[kLanes]) {
    HWY_DYNAMIC_DISPATCH(transportPressLanesKernel)
    (table, pairs, rights, pull, prior, samples, press, valid);
}

void sampleTransportLanes(const ExtendedLightTable& table, const double* t, int samples,
                          float* out) {
    HWY_DYNAMIC_DISPATCH(sampleTransportLanesKernel)(table, t, samples, out);
}

}  // namespace vpe::fit

#endif  // HWY_ONCE
