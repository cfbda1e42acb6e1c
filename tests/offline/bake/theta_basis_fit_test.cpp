// SPDX-License-Identifier: MIT
// The bake's θs basis: the second moment it accumulates, and the functions it fits —
// orthonormal over [0, π] once rounded to floats, spanning the textures' θs parts when they
// lie in K dimensions, ordered by the energy they keep, signed deterministically — and the
// sizes it refuses.
#include "vpe/bake/theta_basis_fit.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/theta_basis.h"

namespace vpe {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Texels (bundle layout 3·k + c) whose θs parts are random combinations of `functions` (each
// 2M + 1 coefficients), plus `noise` of every θ-function; kd random.
std::vector<float> texels(int harmonics, const std::vector<std::vector<double>>& functions,
                          std::size_t count, double noise, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    const int n = proto::thetaFunctionCount(harmonics);
    const auto perTexel = static_cast<std::size_t>(3 * proto::coefficientCount(harmonics));
    std::vector<float> values(count * perTexel);
    for (std::size_t t = 0; t < count; ++t) {
        for (int c = 0; c < 3; ++c) {
            values[t * perTexel + static_cast<std::size_t>(c)] = static_cast<float>(normal(random));
            std::vector<double> g(static_cast<std::size_t>(n), 0.0);
            for (std::size_t f = 0; f < functions.size(); ++f) {
                // Decreasing spread: the first function dominates.
                const double weight = normal(random) / static_cast<double>(f + 1);
                for (int i = 0; i < n; ++i) {
                    g[static_cast<std::size_t>(i)] +=
                        weight * functions[f][static_cast<std::size_t>(i)];
                }
            }
            for (int i = 0; i < n; ++i) {
                values[t * perTexel + static_cast<std::size_t>(3 * (i + 1) + c)] =
                    static_cast<float>(g[static_cast<std::size_t>(i)] + noise * normal(random));
            }
        }
    }
    return values;
}

// ∫₀^π of two functions given by their coefficients.
double innerProduct(const float* a, const float* b, int n) {
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            sum += static_cast<double>(a[i]) * static_cast<double>(b[j]) * proto::thetaGram(i, j);
        }
    }
    return sum;
}

// The largest |∫ h_i h_j − δ_ij| of a fitted basis.
double orthonormalityError(const bake::ThetaBasisFit& fit, int harmonics) {
    const int n = proto::thetaFunctionCount(harmonics);
    const int k = static_cast<int>(fit.functions.size()) / n;
    double worst = 0;
    for (int a = 0; a < k; ++a) {
        for (int b = 0; b < k; ++b) {
            const double p = innerProduct(&fit.functions[static_cast<std::size_t>(a * n)],
                                          &fit.functions[static_cast<std::size_t>(b * n)], n);
            worst = std::max(worst, std::fabs(p - (a == b ? 1.0 : 0.0)));
        }
    }
    return worst;
}

std::vector<double> phi(int harmonics, std::initializer_list<std::pair<int, double>> terms) {
    std::vector<double> f(static_cast<std::size_t>(proto::thetaFunctionCount(harmonics)), 0.0);
    for (const auto& [i, value] : terms) {
        f[static_cast<std::size_t>(i)] = value;
    }
    return f;
}

TEST(ThetaMoment, SumsEveryValidChannelsOuterProduct) {
    const int harmonics = 2;
    const int n = proto::thetaFunctionCount(harmonics);
    const std::vector<float> values =
        texels(harmonics, {phi(harmonics, {{0, 1.0}, {3, 0.5}})}, 5000, 0.3, 1);
    const std::vector<unsigned char> valid = [] {
        std::vector<unsigned char> v(5000, 1);
        v[7] = v[4000] = 0;
        return v;
    }();
    bake::ThetaMoment moment(harmonics);
    moment.add(values, valid);
    moment.add(std::span<const float>(values).first(18 * 10));  // ten more, all valid
    EXPECT_EQ(moment.samples(), 3u * (4998 + 10));
    std::vector<double> expected(static_cast<std::size_t>(n * n), 0.0);
    const auto accumulate = [&](std::size_t t) {
        for (int c = 0; c < 3; ++c) {
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) {
                    expected[static_cast<std::size_t>(i * n + j)] +=
                        static_cast<double>(
                            values[t * 18 + static_cast<std::size_t>(3 * (i + 1) + c)]) *
                        static_cast<double>(
                            values[t * 18 + static_cast<std::size_t>(3 * (j + 1) + c)]);
                }
            }
        }
    };
    for (std::size_t t = 0; t < 5000; ++t) {
        if (valid[t]) {
            accumulate(t);
        }
    }
    for (std::size_t t = 0; t < 10; ++t) {
        accumulate(t);
    }
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_NEAR(moment.moment()[i], expected[i], 1e-9 * std::fabs(expected[i]) + 1e-9) << i;
    }
}

TEST(ThetaBasisFit, CountsTheIndependentThetaFunctions) {
    // The Gram matrix's eigenvalues above 1e-10 of the largest: all of them up to M = 6,
    // then sums of sines start to match sums of cosines on [0, π].
    EXPECT_EQ(bake::independentThetaFunctions(0), 1);
    EXPECT_EQ(bake::independentThetaFunctions(1), 3);
    EXPECT_EQ(bake::independentThetaFunctions(6), 13);
    EXPECT_EQ(bake::independentThetaFunctions(8), 16);
    EXPECT_EQ(bake::independentThetaFunctions(10), 18);
}

TEST(ThetaBasisFit, SpansTexturesThatLieInKFunctionsAndOrdersByEnergy) {
    const int harmonics = 4;
    const int n = proto::thetaFunctionCount(harmonics);
    // Two θs functions, neither orthogonal nor normalized over [0, π].
    const std::vector<std::vector<double>> shapes{
        phi(harmonics, {{0, 0.5}, {1, 0.4}, {3, 0.2}, {2, 0.1}}),
        phi(harmonics, {{2, 0.3}, {4, -0.2}, {5, 0.1}})};
    const std::vector<float> values = texels(harmonics, shapes, 4000, 0.0, 2);
    bake::ThetaMoment moment(harmonics);
    moment.add(values);

    const bake::ThetaBasisFit two = bake::fitThetaBasis(moment, 2);
    ASSERT_EQ(two.functions.size(), static_cast<std::size_t>(2 * n));
    EXPECT_EQ(proto::checkThetaBasis(harmonics, two.functions), "");
    EXPECT_LT(orthonormalityError(two, harmonics), 1e-6);
    EXPECT_NEAR(two.energyKept, 1.0, 1e-6);
    // Every texel's θs part is reproduced by its projection.
    const proto::ThetaBasis basis = proto::ThetaBasis::orthonormal(harmonics, two.functions);
    const auto perTexel = static_cast<std::size_t>(3 * proto::coefficientCount(harmonics));
    std::vector<double> material(static_cast<std::size_t>(proto::thetaMaterialSize(2)));
    for (std::size_t t = 0; t < 4000; t += 97) {
        proto::projectToThetaBasis(basis, &values[t * perTexel], material.data());
        for (int c = 0; c < 3; ++c) {
            for (double theta = 0; theta <= kPi; theta += 0.1) {
                double truth = 0, projected = 0;
                for (int i = 0; i < n; ++i) {
                    truth += static_cast<double>(
                                 values[t * perTexel + static_cast<std::size_t>(3 * (i + 1) + c)]) *
                             proto::thetaFunctionValue(i, theta);
                }
                for (int j = 0; j < 2; ++j) {
                    projected +=
                        material[static_cast<std::size_t>(3 * (1 + j) + c)] * basis.value(j, theta);
                }
                EXPECT_NEAR(projected, truth, 1e-5) << "texel " << t << " θs " << theta;
            }
        }
    }
    // One function keeps less, the dominant one: the same as the first of two.
    const bake::ThetaBasisFit one = bake::fitThetaBasis(moment, 1);
    EXPECT_LT(one.energyKept, two.energyKept);
    EXPECT_GT(one.energyKept, 0.5);
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(one.functions[static_cast<std::size_t>(i)],
                    two.functions[static_cast<std::size_t>(i)], 1e-5);
    }
    // Each function's largest coefficient is positive.
    for (int j = 0; j < 2; ++j) {
        float largest = 0;
        for (int i = 0; i < n; ++i) {
            const float value = two.functions[static_cast<std::size_t>(j * n + i)];
            largest = std::fabs(value) > std::fabs(largest) ? value : largest;
        }
        EXPECT_GT(largest, 0.0f) << "function " << j;
    }
}

TEST(ThetaBasisFit, StaysOrthonormalInFloatsOrSaysSo) {
    // Noisy textures at M = 10 use every direction, the nearly dependent ones included.
    const int harmonics = 10;
    const std::vector<float> values =
        texels(harmonics,
               {phi(harmonics, {{0, 1.0}, {1, 0.8}, {3, 0.5}, {5, 0.3}, {7, 0.2}}),
                phi(harmonics, {{2, 0.5}, {4, 0.3}, {6, -0.2}}), phi(harmonics, {{9, 0.4}})},
               3000, 0.05, 3);
    bake::ThetaMoment moment(harmonics);
    moment.add(values);
    double previous = 0;
    for (int k = 1; k <= 16; ++k) {
        const bake::ThetaBasisFit fit = bake::fitThetaBasis(moment, k);
        EXPECT_EQ(proto::checkThetaBasis(harmonics, fit.functions), "") << "K = " << k;
        // Measured: 6.4e-8 up to K = 12 (float rounding), then 9.8e-8, 2.1e-7, 1.4e-6 and
        // 3.5e-6 at K = 13 … 16 as the nearly dependent directions come in.
        EXPECT_LT(orthonormalityError(fit, harmonics), k <= 12 ? 1e-7 : 1e-5) << "K = " << k;
        EXPECT_GT(fit.energyKept, previous) << "K = " << k;
        previous = fit.energyKept;
    }
    EXPECT_GT(previous, 1.0 - 1e-6);
    // At K = 17 and 18 the last directions' coefficients reach 1e4, and rounding them to floats
    // moves their inner products past 1e-4 (3e-4 measured at K = 18) but within what rounding
    // can do, which the reader allows: both are accepted, as the device will accept them.
    for (int k : {17, 18}) {
        EXPECT_EQ(proto::checkThetaBasis(harmonics, bake::fitThetaBasis(moment, k).functions), "")
            << "K = " << k;
    }
    // The allowance is rounding's and no more: a well-conditioned function moved by 1e-3 is
    // refused.
    std::vector<float> damaged = bake::fitThetaBasis(moment, 18).functions;
    damaged[1] += 1e-3F;
    EXPECT_TRUE(proto::checkThetaBasis(harmonics, damaged).starts_with("functions 0 and "))
        << proto::checkThetaBasis(harmonics, damaged);
}

TEST(ThetaBasisFit, KeepsEverythingOfAnEmptyTexture) {
    bake::ThetaMoment moment(3);
    const bake::ThetaBasisFit fit = bake::fitThetaBasis(moment, 2);
    EXPECT_EQ(fit.energyKept, 1.0);
    EXPECT_EQ(proto::checkThetaBasis(3, fit.functions), "");
}

TEST(ThetaBasisFit, RefusesSizesOutsideTheIndependentFunctions) {
    bake::ThetaMoment moment(10);
    for (int size : {0, -1, 19, 21, 99}) {
        try {
            bake::fitThetaBasis(moment, size);
            ADD_FAILURE() << size << " accepted";
        } catch (const common::InputError& error) {
            EXPECT_EQ(std::string(error.what()),
                      "θs basis: " + std::to_string(size) +
                          " functions, outside 1..18 (the θs functions of M = 10 independent "
                          "over [0, π])");
        }
    }
}

}  // namespace
}  // namespace vpe
