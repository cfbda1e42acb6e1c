// SPDX-License-Identifier: MIT
// The Fourier BRDF model (Esumi, Migita, Shakunaga, eq. 16): the one definition of the basis,
// its coefficient layout and its evaluation, shared by the fitter, the CPU reference renderer
// and (mirrored) the shader. See proto/MODEL.md for units and conventions.
#pragma once

#include <cmath>

namespace vpe::proto {

// Per colour channel the model is
//
//   f(θd, θs) = kd·max(cos θd, 0) + a0/√2 + Σ_{m=1..M} (a_m cos mθs + b_m sin mθs)
//
// with θd the angle between light and normal and θs ∈ [0, π] the angle between the light's
// mirror direction and the view. (The paper writes the Lambert coefficient as a_1^d; we call
// it kd so it cannot be confused with the first harmonic a_1.)
//
// Coefficients are interleaved, [kd, a0, a1, b1, a2, b2, ..., aM, bM], so that a model with
// fewer harmonics is a prefix of one with more: truncating M is taking the first 2M + 2.

inline constexpr int kDefaultHarmonics = 10;
inline constexpr double kDefaultLambda = 3.14;
// Upper bound for fixed-size buffers; the paper's sweep goes to M = 15.
inline constexpr int kMaxHarmonics = 24;

inline constexpr int kLambertIndex = 0;
inline constexpr int kConstantIndex = 1;
inline constexpr double kConstantBasis = 0.70710678118654752440;  // 1/√2, the a0 basis value

constexpr int coefficientCount(int harmonics) {
    return 2 * harmonics + 2;
}
constexpr int cosineIndex(int m) {
    return 2 * m;
}
constexpr int sineIndex(int m) {
    return 2 * m + 1;
}
// The harmonic m a coefficient belongs to (0 for kd and a0).
constexpr int harmonicOf(int index) {
    return index < 2 ? 0 : index / 2;
}
// Weight of a coefficient in the smoothness penalty λ Σ m² (a_m² + b_m²) (paper eq. 19): the
// squared norm of g'(θs) by Parseval. The diffuse terms are not penalized.
constexpr double smoothnessWeight(int index) {
    const int m = harmonicOf(index);
    return static_cast<double>(m) * m;
}

// Steps through cos mθ and sin mθ for m = 1, 2, ... by the Chebyshev recurrence
// X_{m+1} = 2c X_m − X_{m-1} in c = cos θ, which both sequences obey (cos mθ = T_m(c),
// sin mθ = sin θ · U_{m-1}(c)). No trigonometric call per harmonic; θ ∈ [0, π] makes
// sin θ = √(1 − c²) exact. T may be a scalar or a SIMD pack with arithmetic operators and
// ADL-visible fmax, fmin and sqrt.
template <typename T>
class HarmonicRecurrence {
public:
    explicit HarmonicRecurrence(T cosTheta) {
        using std::fmax;
        using std::fmin;
        using std::sqrt;
        const T c = fmin(fmax(cosTheta, T(-1)), T(1));
        twoC_ = c + c;
        cosPrev_ = T(1);                           // cos 0
        cosCur_ = c;                               // cos θ
        sinPrev_ = T(0);                           // sin 0
        sinCur_ = sqrt(fmax(T(1) - c * c, T(0)));  // sin θ
    }
    T cosine() const { return cosCur_; }  // cos mθ
    T sine() const { return sinCur_; }    // sin mθ
    void next() {                         // m → m + 1
        const T cosNext = twoC_ * cosCur_ - cosPrev_;
        const T sinNext = twoC_ * sinCur_ - sinPrev_;
        cosPrev_ = cosCur_;
        cosCur_ = cosNext;
        sinPrev_ = sinCur_;
        sinCur_ = sinNext;
    }

private:
    T twoC_, cosPrev_, cosCur_, sinPrev_, sinCur_;
};

// The Lambert basis value: max(cos θd, 0).
template <typename T>
inline T lambertBasis(T cosThetaD) {
    using std::fmax;
    return fmax(cosThetaD, T(0));
}

// Writes the 2M + 2 basis values of one sample into basis[], in the coefficient layout.
template <typename T>
inline void fourierBasis(T cosThetaD, T cosThetaS, int harmonics, T* basis) {
    basis[kLambertIndex] = lambertBasis(cosThetaD);
    basis[kConstantIndex] = T(kConstantBasis);
    HarmonicRecurrence<T> harmonic(cosThetaS);
    for (int m = 1; m <= harmonics; ++m, harmonic.next()) {
        basis[cosineIndex(m)] = harmonic.cosine();
        basis[sineIndex(m)] = harmonic.sine();
    }
}

// Evaluates one channel: coefficients holds 2M + 2 values in the layout above.
template <typename T, typename Coefficient>
inline T evaluateFourierBrdf(const Coefficient* coefficients, int harmonics, T cosThetaD,
                             T cosThetaS) {
    HarmonicRecurrence<T> harmonic(cosThetaS);
    T specular = T(0);
    for (int m = 1; m <= harmonics; ++m, harmonic.next()) {
        specular = specular + T(coefficients[cosineIndex(m)]) * harmonic.cosine() +
                   T(coefficients[sineIndex(m)]) * harmonic.sine();
    }
    return T(coefficients[kLambertIndex]) * lambertBasis(cosThetaD) +
           T(coefficients[kConstantIndex]) * T(kConstantBasis) + specular;
}

// Evaluates the three colour channels at one angle pair, sharing the recurrence (most of a
// channel's cost): out[c] is exactly evaluateFourierBrdf(coefficients + c · channelStride, …),
// the same operations in the same order. The extended fit predicts every channel of every
// sample several times per texel.
template <typename T, typename Coefficient>
inline void evaluateFourierBrdfRgb(const Coefficient* coefficients, int channelStride,
                                   int harmonics, T cosThetaD, T cosThetaS, T (&out)[3]) {
    const Coefficient* channel[3] = {coefficients, coefficients + channelStride,
                                     coefficients + 2 * channelStride};
    HarmonicRecurrence<T> harmonic(cosThetaS);
    T specular[3] = {T(0), T(0), T(0)};
    for (int m = 1; m <= harmonics; ++m, harmonic.next()) {
        for (int c = 0; c < 3; ++c) {
            specular[c] = specular[c] + T(channel[c][cosineIndex(m)]) * harmonic.cosine() +
                          T(channel[c][sineIndex(m)]) * harmonic.sine();
        }
    }
    const T lambert = lambertBasis(cosThetaD);
    for (int c = 0; c < 3; ++c) {
        out[c] = T(channel[c][kLambertIndex]) * lambert +
                 T(channel[c][kConstantIndex]) * T(kConstantBasis) + specular[c];
    }
}

// The direct form with one trigonometric call per harmonic: slow, for tests only.
inline double evaluateFourierBrdfDirect(const double* coefficients, int harmonics, double thetaD,
                                        double thetaS) {
    double value = coefficients[kLambertIndex] * std::fmax(std::cos(thetaD), 0.0) +
                   coefficients[kConstantIndex] / std::sqrt(2.0);
    for (int m = 1; m <= harmonics; ++m) {
        value += coefficients[cosineIndex(m)] * std::cos(m * thetaS) +
                 coefficients[sineIndex(m)] * std::sin(m * thetaS);
    }
    return value;
}

}  // namespace vpe::proto
