// SPDX-License-Identifier: MIT
// The θs basis contract (theta_basis.h): the closed-form Gram matrix against quadrature, the
// table parameter and its inverse, projection onto the full and onto an orthonormal basis as
// least-squares fits over [0, π], the sampled table, and what checkThetaBasis refuses.
#include "vpe/proto/theta_basis.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ∫₀^π f by composite Simpson on `intervals` (even) intervals: far below 1e-9 for the products
// of harmonics up to M = 12 tested here with 20,000 intervals (error ∝ frequency⁴ / N⁴).
template <typename F>
double integrate(const F& f, int intervals = 20000) {
    const double h = kPi / intervals;
    double sum = f(0.0) + f(kPi);
    for (int k = 1; k < intervals; ++k) {
        sum += (k % 2 == 1 ? 4.0 : 2.0) * f(k * h);
    }
    return sum * h / 3.0;
}

// g(θ) = Σ_i g_i φ_i(θ).
double thetaPart(const std::vector<double>& g, double theta) {
    double sum = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
        sum += g[i] * thetaFunctionValue(static_cast<int>(i), theta);
    }
    return sum;
}

double innerProduct(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (std::size_t j = 0; j < b.size(); ++j) {
            sum += a[i] * b[j] * thetaGram(static_cast<int>(i), static_cast<int>(j));
        }
    }
    return sum;
}

// Gram–Schmidt under ∫₀^π, then rounded to floats as a bundle stores them.
std::vector<float> orthonormalized(const std::vector<std::vector<double>>& functions) {
    std::vector<std::vector<double>> done;
    for (std::vector<double> f : functions) {
        for (int pass = 0; pass < 2; ++pass) {  // twice: rounding (Kahan's "twice is enough")
            for (const std::vector<double>& e : done) {
                const double p = innerProduct(f, e);
                for (std::size_t i = 0; i < f.size(); ++i) {
                    f[i] -= p * e[i];
                }
            }
        }
        const double norm = std::sqrt(innerProduct(f, f));
        for (double& value : f) {
            value /= norm;
        }
        done.push_back(f);
    }
    std::vector<float> flat;
    for (const std::vector<double>& f : done) {
        flat.insert(flat.end(), f.begin(), f.end());
    }
    return flat;
}

// Coefficients of one texel, bundle layout 3·k + c, random in [−1, 1].
std::vector<double> randomTexel(int harmonics, std::mt19937& random) {
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::vector<double> texel(static_cast<std::size_t>(3 * coefficientCount(harmonics)));
    for (double& v : texel) {
        v = value(random);
    }
    return texel;
}

// Channel c's θs part of a texel: coefficients 1 … 2M + 1.
std::vector<double> channelThetaPart(const std::vector<double>& texel, int harmonics, int c) {
    std::vector<double> g(static_cast<std::size_t>(thetaFunctionCount(harmonics)));
    for (std::size_t i = 0; i < g.size(); ++i) {
        g[i] = texel[3 * (i + 1) + static_cast<std::size_t>(c)];
    }
    return g;
}

// Σ_j u_j h_j(θ) of channel c of a material.
double projectedValue(const ThetaBasis& basis, const std::vector<double>& material, int c,
                      double theta) {
    double sum = 0;
    for (int j = 0; j < basis.size; ++j) {
        sum += material[static_cast<std::size_t>(3 * (1 + j) + c)] * basis.value(j, theta);
    }
    return sum;
}

TEST(ThetaGram, MatchesQuadratureAndIsSymmetric) {
    const int n = thetaFunctionCount(12);
    const int intervals = 20000;
    // φ_i at the quadrature nodes, once.
    std::vector<std::vector<double>> nodes(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k <= intervals; ++k) {
            nodes[static_cast<std::size_t>(i)].push_back(
                thetaFunctionValue(i, kPi * k / intervals));
        }
    }
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const auto& a = nodes[static_cast<std::size_t>(i)];
            const auto& b = nodes[static_cast<std::size_t>(j)];
            double sum = a.front() * b.front() + a.back() * b.back();
            for (int k = 1; k < intervals; ++k) {
                sum += (k % 2 == 1 ? 4.0 : 2.0) * a[static_cast<std::size_t>(k)] *
                       b[static_cast<std::size_t>(k)];
            }
            const double quadrature = sum * (kPi / intervals) / 3.0;
            EXPECT_NEAR(thetaGram(i, j), quadrature, 1e-9) << i << ", " << j;
            EXPECT_EQ(thetaGram(i, j), thetaGram(j, i)) << i << ", " << j;
        }
    }
}

TEST(ThetaTableParameter, EndsMiddleMonotoneAndContinuous) {
    EXPECT_EQ(thetaTableParameter(1.0), 0.0);
    EXPECT_EQ(thetaTableParameter(-1.0), 1.0);
    EXPECT_NEAR(thetaTableParameter(0.0), 0.5, 1e-15);
    // Continuous at cos θs = 0, where the two branches meet.
    const double tiny = 1e-12;
    EXPECT_NEAR(thetaTableParameter(tiny), 0.5, 1e-12);
    EXPECT_NEAR(thetaTableParameter(-tiny), 0.5, 1e-12);
    // Strictly decreasing in cos θs (increasing in θs): walking cos θs down, x rises.
    double previous = thetaTableParameter(1.0);
    for (int k = 1; k <= 100000; ++k) {
        const double cosine = 1.0 - 2.0 * k / 100000;
        const double x = thetaTableParameter(cosine);
        ASSERT_GT(x, previous) << "cos θs " << cosine;
        previous = x;
    }
    // The float instantiation the shaders' CPU mirror uses agrees.
    for (double cosine : {-0.9, -0.3, 0.0, 0.2, 0.99}) {
        EXPECT_NEAR(thetaTableParameter(static_cast<float>(cosine)), thetaTableParameter(cosine),
                    1e-6);
    }
}

TEST(ThetaTableParameter, InvertedByThetaAtTableParameter) {
    for (int k = 0; k <= 10000; ++k) {
        const double x = k / 10000.0;
        const double theta = thetaAtTableParameter(x);
        ASSERT_GE(theta, 0.0);
        ASSERT_LE(theta, kPi);
        EXPECT_NEAR(thetaTableParameter(std::cos(theta)), x, 1e-12) << "x " << x;
    }
    // And the other way, away from the ends, where cos θs itself loses θs to rounding.
    for (int k = 1; k < 1000; ++k) {
        const double theta = kPi * k / 1000;
        EXPECT_NEAR(thetaAtTableParameter(thetaTableParameter(std::cos(theta))), theta, 1e-12)
            << "θs " << theta;
    }
}

TEST(ThetaBasis, FullReproducesEveryTexelExactly) {
    std::mt19937 random(7);
    for (int harmonics : {0, 1, 4, 10, kMaxHarmonics}) {
        const ThetaBasis basis = ThetaBasis::full(harmonics);
        ASSERT_EQ(basis.size, thetaFunctionCount(harmonics));
        const std::vector<double> texel = randomTexel(harmonics, random);
        std::vector<double> material(static_cast<std::size_t>(thetaMaterialSize(basis.size)));
        projectToThetaBasis(basis, texel.data(), material.data());
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(material[static_cast<std::size_t>(c)],
                      texel[static_cast<std::size_t>(3 * kLambertIndex + c)]);
            const std::vector<double> g = channelThetaPart(texel, harmonics, c);
            for (int j = 0; j < basis.size; ++j) {  // the weights are the coefficients
                EXPECT_EQ(material[static_cast<std::size_t>(3 * (1 + j) + c)],
                          g[static_cast<std::size_t>(j)]);
            }
            for (double theta = 0; theta <= kPi; theta += 0.01) {
                EXPECT_NEAR(projectedValue(basis, material, c, theta), thetaPart(g, theta), 1e-12)
                    << "M " << harmonics << " θs " << theta;
            }
        }
    }
}

// An orthonormal basis of three functions spanned by 1/√2, cos θs, sin θs and sin 2θs.
class OrthonormalThetaBasis : public ::testing::Test {
protected:
    static constexpr int kHarmonics = 3;
    static std::vector<double> phi(std::initializer_list<std::pair<int, double>> terms) {
        std::vector<double> f(static_cast<std::size_t>(thetaFunctionCount(kHarmonics)), 0.0);
        for (const auto& [i, value] : terms) {
            f[static_cast<std::size_t>(i)] = value;
        }
        return f;
    }
    const std::vector<float> functions_ = orthonormalized(
        {phi({{0, 1.0}, {2, 0.5}}), phi({{1, 1.0}, {4, -0.3}}), phi({{2, 1.0}, {0, 0.2}})});
    const ThetaBasis basis_ = ThetaBasis::orthonormal(kHarmonics, functions_);
};

TEST_F(OrthonormalThetaBasis, ReproducesFunctionsInItsSpan) {
    ASSERT_EQ(checkThetaBasis(kHarmonics, functions_), "");
    ASSERT_EQ(basis_.size, 3);
    // A texel whose three θs parts are combinations of the basis functions.
    const int n = thetaFunctionCount(kHarmonics);
    std::vector<double> texel(static_cast<std::size_t>(3 * coefficientCount(kHarmonics)), 0.0);
    const double weights[3][3] = {{0.7, -0.2, 1.5}, {-1.0, 0.4, 0.0}, {0.3, 0.3, -0.8}};
    for (int c = 0; c < 3; ++c) {
        texel[static_cast<std::size_t>(c)] = 0.1 * (c + 1);  // kd
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < n; ++i) {
                texel[static_cast<std::size_t>(3 * (i + 1) + c)] +=
                    weights[c][j] *
                    static_cast<double>(functions_[static_cast<std::size_t>(j * n + i)]);
            }
        }
    }
    std::vector<double> material(static_cast<std::size_t>(thetaMaterialSize(basis_.size)));
    projectToThetaBasis(basis_, texel.data(), material.data());
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(material[static_cast<std::size_t>(c)], texel[static_cast<std::size_t>(c)]);
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(material[static_cast<std::size_t>(3 * (1 + j) + c)], weights[c][j], 1e-6);
        }
        const std::vector<double> g = channelThetaPart(texel, kHarmonics, c);
        for (double theta = 0; theta <= kPi; theta += 0.01) {
            EXPECT_NEAR(projectedValue(basis_, material, c, theta), thetaPart(g, theta), 1e-6);
        }
    }
}

TEST_F(OrthonormalThetaBasis, IsTheLeastSquaresFitOtherwise) {
    std::mt19937 random(11);
    const std::vector<double> texel = randomTexel(kHarmonics, random);
    std::vector<double> material(static_cast<std::size_t>(thetaMaterialSize(basis_.size)));
    projectToThetaBasis(basis_, texel.data(), material.data());
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> g = channelThetaPart(texel, kHarmonics, c);
        for (int j = 0; j < basis_.size; ++j) {
            // The weight is ∫₀^π h_j g, integrated numerically …
            const double u = material[static_cast<std::size_t>(3 * (1 + j) + c)];
            EXPECT_NEAR(
                u, integrate([&](double t) { return basis_.value(j, t) * thetaPart(g, t); }), 1e-9);
            // … so the residual is orthogonal to every basis function: the least-squares fit (to
            // the functions' orthonormality, which floats hold to about 1e-7).
            EXPECT_NEAR(integrate([&](double t) {
                            return basis_.value(j, t) *
                                   (thetaPart(g, t) - projectedValue(basis_, material, c, t));
                        }),
                        0.0, 1e-6);
        }
    }
}

TEST(ThetaTable, SamplesAreTheFunctionsAndInterpolateClosely) {
    const int harmonics = 10;
    const int samples = 1024;
    const ThetaBasis basis = ThetaBasis::full(harmonics);
    const ThetaTable table = ThetaTable::of(basis, samples);
    ASSERT_EQ(table.size, basis.size);
    ASSERT_EQ(table.values.size(), static_cast<std::size_t>(samples * basis.size));
    double worst = 0;
    for (int j = 0; j < basis.size; ++j) {
        for (int s = 0; s < samples; ++s) {
            const double x = static_cast<double>(s) / (samples - 1);
            EXPECT_NEAR(table.sample(j, x), basis.value(j, thetaAtTableParameter(x)), 1e-6)
                << "function " << j << " sample " << s;
        }
        // Halfway between samples, where linear interpolation is worst.
        for (int s = 0; s + 1 < samples; ++s) {
            const double x = (s + 0.5) / (samples - 1);
            worst = std::max(
                worst, std::fabs(table.sample(j, x) - basis.value(j, thetaAtTableParameter(x))));
        }
    }
    // Measured: 1.91e-4, at cos 10θs and sin 10θs where θs moves fastest per sample. That is
    // the bound h²/8 · max |φ''| with h = 4 / 1023 (dx/dθs ≥ 1/4) and max |φ''| = 100:
    // 100 · (4 / 1023)² / 8 = 1.91e-4.
    EXPECT_LT(worst, 1.95e-4);
    RecordProperty("worst_interpolation_error", std::to_string(worst));
}

TEST(CheckThetaBasis, AcceptsOrthonormalFunctionsAndRefusesTheRest) {
    const int harmonics = 2;                                      // n = 5
    const float c = static_cast<float>(std::sqrt(2.0 / kPi));     // √(2/π) cos θs has norm 1
    const std::vector<float> good{0, c, 0, 0, 0, 0, 0, 0, c, 0};  // cos θs, cos 2θs
    EXPECT_EQ(checkThetaBasis(harmonics, good), "");
    EXPECT_EQ(checkThetaBasis(harmonics, std::vector<float>{}),
              "0 values, not a positive multiple of 2M + 1 = 5");
    EXPECT_EQ(checkThetaBasis(harmonics, std::vector<float>(7, 0.0f)),
              "7 values, not a positive multiple of 2M + 1 = 5");
    EXPECT_EQ(checkThetaBasis(harmonics, std::vector<float>(30, 0.0f)),
              "6 functions, more than 2M + 1 = 5");
    std::vector<float> bad = good;
    bad[3] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(checkThetaBasis(harmonics, bad), "a value is not finite");
    bad[3] = std::numeric_limits<float>::infinity();
    EXPECT_EQ(checkThetaBasis(harmonics, bad), "a value is not finite");
    bad = good;
    bad[1] = 1.0f;  // cos θs with norm √(π/2)
    EXPECT_EQ(checkThetaBasis(harmonics, bad),
              "functions 0 and 0 are not orthonormal over [0, π] (inner product 1.570796)");
    bad = good;
    bad[2] = 0.3f;  // sin θs is not orthogonal to cos 2θs on [0, π]
    EXPECT_NE(checkThetaBasis(harmonics, bad).find("not orthonormal"), std::string::npos);
    // Within the tolerance (1e-4) still accepted: floats as the bake rounds them.
    bad = good;
    bad[1] *= 1.00001f;
    EXPECT_EQ(checkThetaBasis(harmonics, bad), "");
}

}  // namespace
}  // namespace vpe::proto
