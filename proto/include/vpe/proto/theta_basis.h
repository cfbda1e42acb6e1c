// SPDX-License-Identifier: MIT
// The θs basis (proto/MODEL.md, "Rendering in a θs basis"): the model's θs part re-expressed in
// K functions h_j(θs), so that a renderer evaluates per pixel K numbers per channel against a
// table of h_j instead of 2M + 1 harmonics. Header-only, no dependencies: the bake chooses the
// functions (offline), the device and the CPU reference share everything here.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "vpe/proto/fourier_brdf.h"

namespace vpe::proto {

// The θs part of one channel, g(θs) = a0/√2 + Σ_m (a_m cos mθs + b_m sin mθs), has n = 2M + 1
// coefficients: θ-function i is φ_0 = 1/√2, φ_{2m−1} = cos mθs, φ_{2m} = sin mθs — coefficient
// i + 1 of the model's layout (fourier_brdf.h: kd first).
constexpr int thetaFunctionCount(int harmonics) {
    return 2 * harmonics + 1;
}

inline double thetaFunctionValue(int i, double theta) {
    if (i == 0) {
        return kConstantBasis;
    }
    const int m = (i + 1) / 2;
    return i % 2 == 1 ? std::cos(m * theta) : std::sin(m * theta);
}

// ∫₀^π φ_i φ_j dθ in closed form: the inner product that measures a θs function's error over
// the angles a renderer meets (θs ∈ [0, π]). On [0, π] the cosines and sines are not
// orthogonal to each other (only over a whole period), and the Gram matrix is nearly singular:
// sums of sines can match sums of cosines on a half period to 1e-13.
inline double thetaGram(int i, int j) {
    constexpr double kPi = 3.14159265358979323846;
    if (i > j) {
        std::swap(i, j);
    }
    const auto parity = [](int k) { return k % 2 == 0 ? 1.0 : -1.0; };  // (−1)^k
    if (i == 0) {
        if (j == 0) {
            return kPi / 2;  // ∫ ½
        }
        const int m = (j + 1) / 2;
        return j % 2 == 1 ? 0.0 : kConstantBasis * (1 - parity(m)) / m;  // ∫ sin mθ / √2
    }
    const int m = (i + 1) / 2, k = (j + 1) / 2;
    const bool iCos = i % 2 == 1, jCos = j % 2 == 1;
    if (iCos == jCos) {
        return m == k ? kPi / 2 : 0.0;
    }
    // ∫ cos aθ sin bθ = ½ ∫ [sin (b + a)θ + sin (b − a)θ]
    const int a = iCos ? m : k, b = iCos ? k : m;
    const double sum = (1 - parity(a + b)) / (a + b);
    const double difference = a == b ? 0.0 : (1 - parity(b - a)) / (b - a);
    return 0.5 * (sum + difference);
}

// K functions h_j = Σ_i functions[j·n + i] φ_i and the projection that takes a channel's θs
// coefficients g (n values) to its K weights, u = projection · g, so that Σ_j u_j h_j
// approximates g (exactly when g lies in their span).
struct ThetaBasis {
    int harmonics = 0;
    int size = 0;                    // K
    std::vector<double> functions;   // K × n
    std::vector<double> projection;  // K × n

    int functionCount() const { return thetaFunctionCount(harmonics); }

    // φ_i themselves, projection the identity: no approximation (a bundle that carries no
    // basis is rendered so), at n table functions per pixel.
    static ThetaBasis full(int harmonics) {
        ThetaBasis basis;
        basis.harmonics = harmonics;
        basis.size = thetaFunctionCount(harmonics);
        const auto n = static_cast<std::size_t>(basis.size);
        basis.functions.assign(n * n, 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            basis.functions[i * n + i] = 1.0;
        }
        basis.projection = basis.functions;
        return basis;
    }

    // Functions orthonormal in ∫₀^π (as the bake writes them): projection = Hᵀ·Gram, the
    // least-squares fit over θs ∈ [0, π].
    static ThetaBasis orthonormal(int harmonics, std::span<const float> functions) {
        ThetaBasis basis;
        basis.harmonics = harmonics;
        const int n = thetaFunctionCount(harmonics);
        basis.size = static_cast<int>(functions.size()) / n;
        basis.functions.assign(functions.begin(), functions.end());
        basis.projection.assign(functions.size(), 0.0);
        for (int j = 0; j < basis.size; ++j) {
            for (int i = 0; i < n; ++i) {
                double sum = 0;
                for (int k = 0; k < n; ++k) {
                    sum += basis.functions[static_cast<std::size_t>(j * n + k)] * thetaGram(k, i);
                }
                basis.projection[static_cast<std::size_t>(j * n + i)] = sum;
            }
        }
        return basis;
    }

    // h_j(θ).
    double value(int j, double theta) const {
        const int n = functionCount();
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            sum += functions[static_cast<std::size_t>(j * n + i)] * thetaFunctionValue(i, theta);
        }
        return sum;
    }
};

// Why `functions` (K × (2M + 1) values, as a bundle stores them) is not an orthonormal θs
// basis, as a phrase; "" when it is (every ∫₀^π h_i h_j within 1e-4 of δ_ij, plus what rounding
// its coefficients to floats can move it).
inline std::string checkThetaBasis(int harmonics, std::span<const float> functions) {
    const int n = thetaFunctionCount(harmonics);
    if (functions.empty() || functions.size() % static_cast<std::size_t>(n) != 0) {
        return std::to_string(functions.size()) +
               " values, not a positive multiple of 2M + 1 = " + std::to_string(n);
    }
    const int k = static_cast<int>(functions.size()) / n;
    if (k > n) {
        return std::to_string(k) + " functions, more than 2M + 1 = " + std::to_string(n);
    }
    for (const float value : functions) {
        if (!std::isfinite(value)) {
            return "a value is not finite";
        }
    }
    // G·h_a and |h_a| of every function's stored coefficients, for the rounding allowance.
    std::vector<double> gramTimes(functions.size(), 0.0);
    std::vector<double> norms(static_cast<std::size_t>(k), 0.0);
    for (int a = 0; a < k; ++a) {
        for (int i = 0; i < n; ++i) {
            const double value = functions[static_cast<std::size_t>(a * n + i)];
            norms[static_cast<std::size_t>(a)] += value * value;
            for (int j = 0; j < n; ++j) {
                gramTimes[static_cast<std::size_t>(a * n + j)] += value * thetaGram(i, j);
            }
        }
        norms[static_cast<std::size_t>(a)] = std::sqrt(norms[static_cast<std::size_t>(a)]);
    }
    const auto gramNorm = [&](int a) {
        double sum = 0;
        for (int i = 0; i < n; ++i) {
            sum += gramTimes[static_cast<std::size_t>(a * n + i)] *
                   gramTimes[static_cast<std::size_t>(a * n + i)];
        }
        return std::sqrt(sum);
    };
    for (int a = 0; a < k; ++a) {
        for (int b = a; b < k; ++b) {
            double product = 0;
            for (int i = 0; i < n; ++i) {
                product += static_cast<double>(functions[static_cast<std::size_t>(a * n + i)]) *
                           gramTimes[static_cast<std::size_t>(b * n + i)];
            }
            // Rounding exactly orthonormal coefficients c to floats (relative 2⁻²⁴ each) moves
            // cₐᵀ G c_b by at most 2⁻²⁴ (|cₐ|·|G c_b| + |c_b|·|G cₐ|): large for the functions
            // that nearly cancel on [0, π] (coefficients near 1e5), tiny for the others.
            const double rounding = 0x1p-24 * (norms[static_cast<std::size_t>(a)] * gramNorm(b) +
                                               norms[static_cast<std::size_t>(b)] * gramNorm(a));
            if (std::fabs(product - (a == b ? 1.0 : 0.0)) > 1e-4 + rounding) {
                return "functions " + std::to_string(a) + " and " + std::to_string(b) +
                       " are not orthonormal over [0, π] (inner product " +
                       std::to_string(product) + ")";
            }
        }
    }
    return "";
}

// A per-pixel material in a θs basis: 3·(1 + K) values, [kd.r, kd.g, kd.b, u_0.r, u_0.g,
// u_0.b, u_1.r, …]: value 3·q + c is term q (0: kd, 1 + j: u_j) of channel c.
constexpr int thetaMaterialSize(int basisSize) {
    return 3 * (1 + basisSize);
}

// The material of a texel's coefficients (bundle layout 3·k + c, 3·(2M + 2) values).
template <typename In, typename Out>
inline void projectToThetaBasis(const ThetaBasis& basis, const In* coefficients, Out* material) {
    const int n = basis.functionCount();
    for (int c = 0; c < 3; ++c) {
        material[c] = static_cast<Out>(coefficients[3 * kLambertIndex + c]);
        for (int j = 0; j < basis.size; ++j) {
            double u = 0;
            for (int i = 0; i < n; ++i) {
                u += basis.projection[static_cast<std::size_t>(j * n + i)] *
                     static_cast<double>(coefficients[3 * (i + 1) + c]);
            }
            material[3 * (1 + j) + c] = static_cast<Out>(u);
        }
    }
}

// Where a renderer looks θs up: x ∈ [0, 1], x = sin(θs/2)/√2 for θs ≤ π/2 and
// 1 − cos(θs/2)/√2 above, from cos θs with one square root and no inverse trigonometry.
// dx/dθs stays within [1/4, 1/(2√2)] over [0, π], so a table uniform in x samples θs almost
// uniformly and linear interpolation in x is as accurate as in θs.
template <typename T>
inline T thetaTableParameter(T cosThetaS) {
    using std::fabs;
    using std::fmax;
    using std::sqrt;
    const T s = sqrt(fmax(T(0.5) - T(0.5) * fabs(cosThetaS), T(0))) * T(0.70710678118654752440);
    return cosThetaS >= T(0) ? s : T(1) - s;
}

// θs at a table parameter x (the inverse of thetaTableParameter).
inline double thetaAtTableParameter(double x) {
    constexpr double kSqrt2 = 1.41421356237309504880;
    return x <= 0.5 ? 2 * std::asin(std::min(kSqrt2 * x, 1.0))
                    : 2 * std::acos(std::min(kSqrt2 * (1 - x), 1.0));
}

// The table a renderer samples: h_j at x_s = s / (samples − 1), s = 0 … samples − 1;
// values[s·K + j]. Linear interpolation between samples (a GL_LINEAR texture of `samples`
// texels, coordinate (x·(samples − 1) + ½) / samples).
struct ThetaTable {
    int samples = 0;
    int size = 0;  // K
    std::vector<float> values;

    static ThetaTable of(const ThetaBasis& basis, int samples) {
        ThetaTable table;
        table.samples = samples;
        table.size = basis.size;
        table.values.resize(static_cast<std::size_t>(samples) *
                            static_cast<std::size_t>(basis.size));
        for (int s = 0; s < samples; ++s) {
            const double theta = thetaAtTableParameter(static_cast<double>(s) / (samples - 1));
            for (int j = 0; j < basis.size; ++j) {
                table.values[static_cast<std::size_t>(s * basis.size + j)] =
                    static_cast<float>(basis.value(j, theta));
            }
        }
        return table;
    }

    // h_j at parameter x, interpolated as GL_LINEAR does (up to its subtexel rounding).
    double sample(int j, double x) const {
        const double position = std::clamp(x, 0.0, 1.0) * (samples - 1);
        const int s = std::min(static_cast<int>(position), samples - 2);
        const double f = position - s;
        const auto at = [&](int i) {
            return static_cast<double>(values[static_cast<std::size_t>(i * size + j)]);
        };
        return at(s) + f * (at(s + 1) - at(s));
    }
};

}  // namespace vpe::proto
