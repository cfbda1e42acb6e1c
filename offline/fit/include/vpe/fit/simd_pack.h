// SPDX-License-Identifier: MIT
// Pack<S, L>: L lanes of scalar S in one GCC vector, with the arithmetic and the ADL-visible
// fmax/fmin/sqrt that proto's templated model code needs. Lane i is one pixel, so the model's
// own basis function runs on L pixels at once and the fitter shares its definition. Used by the
// extended fit's lane kernels; the BRDF's normal equations are written with Highway instead
// (normal_equations.cpp), with a vector width per SIMD target.
#pragma once

#include <cmath>
#include <cstring>

// A hot loop over packs is compiled for several x86-64 levels and picked at run time, so one
// binary uses AVX-512 where it exists and still runs on any x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define VPE_KERNEL_CLONES \
    __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define VPE_KERNEL_CLONES
#endif

namespace vpe::simd {

// GCC ignores vector_size on a dependent type, so each lane shape is spelled out once.
template <typename S, int L>
struct VectorOf;
template <>
struct VectorOf<double, 8> {
    typedef double Type __attribute__((vector_size(64)));
};

template <typename S, int L>
struct Pack {
    using Vector = typename VectorOf<S, L>::Type;
    static constexpr int kLanes = L;
    Vector v;

    Pack() = default;
    // NOLINTNEXTLINE: broadcast, like a scalar. Element by element, which compiles to one
    // broadcast; `Vector{} + scalar` added 0 to the scalar first, in the innermost loops.
    Pack(S scalar) {
        for (int i = 0; i < L; ++i) {
            v[i] = scalar;
        }
    }
    explicit Pack(Vector vector) : v(vector) {}

    static Pack load(const S* p) {
        Pack r;
        std::memcpy(&r.v, p, sizeof(Vector));
        return r;
    }
    void store(S* p) const { std::memcpy(p, &v, sizeof(Vector)); }
    S operator[](int lane) const { return v[lane]; }

    friend Pack operator+(Pack a, Pack b) { return Pack(a.v + b.v); }
    friend Pack operator-(Pack a, Pack b) { return Pack(a.v - b.v); }
    friend Pack operator*(Pack a, Pack b) { return Pack(a.v * b.v); }
    friend Pack operator/(Pack a, Pack b) { return Pack(a.v / b.v); }
    Pack& operator+=(Pack b) {
        v += b.v;
        return *this;
    }
    friend Pack fmax(Pack a, Pack b) { return Pack(a.v > b.v ? a.v : b.v); }
    friend Pack fmin(Pack a, Pack b) { return Pack(a.v < b.v ? a.v : b.v); }
    friend Pack sqrt(Pack a) {
        Pack r;
        for (int i = 0; i < L; ++i) {
            r.v[i] = std::sqrt(a.v[i]);  // vectorized: the offline code builds with -fno-math-errno
        }
        return r;
    }
};

}  // namespace vpe::simd
