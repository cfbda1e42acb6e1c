// SPDX-License-Identifier: MIT
// The product-to-sum normal-equation kernel against the textbook fit, on every SIMD target the
// kernel is compiled for and this CPU runs.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "vpe/common/input_error.h"
#include "vpe/fit/naive_fourier_fit.h"
#include "vpe/fit/normal_equations.h"

#include "support/synthetic_capture.h"

namespace vpe::fit {
namespace {

// kLanes pixels with random normals, lights, and observations rendered from known
// coefficients (plus optional noise), in the kernel's layout.
struct KernelFixture {
    int harmonics;
    int samples;
    std::vector<KernelLight> lights;
    ChunkGeometry geometry{};
    std::vector<float> values;   // [s][c][lane]
    std::vector<float> weights;  // [s][lane]
    std::vector<double> truth;   // [lane][c][k]
    bool point = false;

    KernelFixture(int m, std::vector<proto::Vec3d> directions, double tilt, double noise,
                  std::uint32_t seed, bool pointLights = false)
        : harmonics(m), samples(static_cast<int>(directions.size())), point(pointLights) {
        std::mt19937 random(seed);
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        std::normal_distribution<double> gaussian(0.0, noise > 0 ? noise : 1.0);
        const int k = proto::coefficientCount(m);
        for (const proto::Vec3d& d : directions) {
            const double scale = point ? 6.0 : 1.0;
            lights.push_back({static_cast<float>(d.x * scale), static_cast<float>(d.y * scale),
                              static_cast<float>(d.z * scale), 1.0f});
        }
        for (int lane = 0; lane < kLanes; ++lane) {
            const proto::Vec3d n = proto::normalized(
                proto::Vec3d{tilt * uniform(random), tilt * uniform(random), 1.0});
            const proto::Vec3d v =
                proto::normalized(proto::Vec3d{0.2 * uniform(random), 0.2 * uniform(random), 1.0});
            const float n3[3] = {static_cast<float>(n.x), static_cast<float>(n.y),
                                 static_cast<float>(n.z)};
            const float v3[3] = {static_cast<float>(v.x), static_cast<float>(v.y),
                                 static_cast<float>(v.z)};
            for (int a = 0; a < 3; ++a) {
                geometry.normal[a][lane] = n3[a];
                geometry.view[a][lane] = v3[a];
                geometry.position[a][lane] = static_cast<float>(0.3 * uniform(random));
            }
        }
        truth.resize(static_cast<std::size_t>(kLanes) * 3 * k);
        for (double& t : truth) {
            t = 0.1 * uniform(random);
        }
        values.assign(static_cast<std::size_t>(samples) * 3 * kLanes, 0.0f);
        weights.assign(static_cast<std::size_t>(samples) * kLanes, 1.0f);
        for (int s = 0; s < samples; ++s) {
            for (int lane = 0; lane < kLanes; ++lane) {
                const auto [angles, irradiance] = anglesOf(s, lane);
                for (int c = 0; c < 3; ++c) {
                    double y = proto::evaluateFourierBrdf(&truth[(lane * 3 + c) * k], m,
                                                          angles.cosThetaD, angles.cosThetaS);
                    if (noise > 0) {
                        y += gaussian(random);
                    }
                    values[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane] =
                        static_cast<float>(y * irradiance);
                }
            }
        }
    }

    // The angles and irradiance of sample s at a lane, computed independently in double.
    std::pair<proto::ReflectionAngles<double>, double> anglesOf(int s, int lane) const {
        const proto::Vec3d n{geometry.normal[0][lane], geometry.normal[1][lane],
                             geometry.normal[2][lane]};
        const proto::Vec3d v{geometry.view[0][lane], geometry.view[1][lane],
                             geometry.view[2][lane]};
        proto::Vec3d l{lights[s].x, lights[s].y, lights[s].z};
        double irradiance = 1.0;
        if (point) {
            const proto::Vec3d d{l.x - geometry.position[0][lane], l.y - geometry.position[1][lane],
                                 l.z - geometry.position[2][lane]};
            irradiance = 1.0 / proto::dot(d, d);  // reference distance 1
            l = proto::normalized(d);
        }
        return {proto::reflectionAngles(proto::normalized(n), l, proto::normalized(v)), irradiance};
    }

    KernelLightSet lightSet() const { return {lights.data(), samples, point, 1.0f}; }
    ChunkObservations observations() const {
        return {values.data(), static_cast<std::size_t>(3 * kLanes), kLanes, weights.data(),
                kLanes};
    }

    NaiveFitResult naive(int lane, double lambda) const {
        std::vector<proto::ReflectionAngles<double>> angles;
        Eigen::MatrixX3d y(samples, 3);
        Eigen::VectorXd w(samples);
        for (int s = 0; s < samples; ++s) {
            const auto [a, irradiance] = anglesOf(s, lane);
            angles.push_back(a);
            for (int c = 0; c < 3; ++c) {
                y(s, c) =
                    values[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane] / irradiance;
            }
            w(s) = weights[static_cast<std::size_t>(s) * kLanes + lane];
        }
        return fitPixelNaive(angles, y, w, harmonics, lambda);
    }

    std::unique_ptr<ChunkSolution> solve(double lambda, AccumulationPrecision precision) const {
        auto sums = std::make_unique<NormalEquationSums>();
        auto solution = std::make_unique<ChunkSolution>();
        accumulateNormalEquations(geometry, lightSet(), observations(), harmonics, precision,
                                  *sums);
        solveNormalEquations(*sums, harmonics, lambda, *solution);
        return solution;
    }
};

std::vector<proto::Vec3d> dome() {
    return testing::domeLights({10, 30, 50, 70, 90}, 12);
}

// Runs each test with the kernels restricted to one SIMD target (AVX-512, AVX2, SSE4, NEON,
// the scalar fallback, ...): every target must give the textbook fit's coefficients.
class NormalEquations : public ::testing::TestWithParam<std::int64_t> {
protected:
    void SetUp() override {
        hwy::SetSupportedTargetsForTest(GetParam());
        ASSERT_EQ(activeKernelTarget(), GetParam()) << "the kernels did not switch target";
    }
    void TearDown() override { hwy::SetSupportedTargetsForTest(0); }
};

INSTANTIATE_TEST_SUITE_P(FitKernelTargets, NormalEquations, ::testing::ValuesIn(kernelTargets()),
                         [](const ::testing::TestParamInfo<std::int64_t>& target) {
                             return std::string(hwy::TargetName(target.param));
                         });

// What VPE_SIMD does for the `vpe` command: every kernel on the target named, any case.
TEST(FitKernelTargets, RestrictingToATargetByNameDispatchesToIt) {
    for (const std::int64_t target : kernelTargets()) {
        std::string name = kernelTargetName(target);
        std::transform(name.begin(), name.end(), name.begin(),
                       [](char c) { return static_cast<char>(std::tolower(c)); });
        restrictKernelTarget(name);
        EXPECT_EQ(activeKernelTarget(), target) << name;
        EXPECT_STREQ(activeKernelTargetName(), kernelTargetName(target));
        hwy::DisableTargets(0);  // the process's own choice again
    }
    EXPECT_EQ(activeKernelTarget(), kernelTargets().front());
    EXPECT_THROW(restrictKernelTarget("AVX9"), common::InputError);
}

// A build that compiled only the baseline would still pass the tests above, on one target.
TEST(FitKernelTargets, EveryVectorUnitOfThisCpuHasItsKernel) {
    const std::vector<std::int64_t> targets = kernelTargets();
    const auto compiled = [&](std::int64_t target) {
        return std::find(targets.begin(), targets.end(), target) != targets.end();
    };
#if defined(__x86_64__)
    // Highway's AVX2 target also needs F16C, which every AVX2 CPU has (clang 14's
    // __builtin_cpu_supports cannot name it).
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
        __builtin_cpu_supports("bmi2")) {
        EXPECT_TRUE(compiled(HWY_AVX2));
    }
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw")) {
        EXPECT_TRUE(compiled(HWY_AVX3) || compiled(HWY_AVX3_DL));
    }
    if (__builtin_cpu_supports("sse4.2")) {
        EXPECT_TRUE(compiled(HWY_SSE4));
    }
#elif defined(__aarch64__)
    EXPECT_TRUE(compiled(HWY_NEON));
#endif
    EXPECT_EQ(activeKernelTarget(), targets.front()) << "the best target runs by default";
}

TEST_P(NormalEquations, ProductToSumMatrixEqualsDesignGram) {
    const KernelFixture f(10, dome(), 0.4, 0.0, 1);
    auto sums = std::make_unique<NormalEquationSums>();
    accumulateNormalEquations(f.geometry, f.lightSet(), f.observations(), 10,
                              AccumulationPrecision::kDouble, *sums);
    const int k = proto::coefficientCount(10);
    std::vector<double> matrix(static_cast<std::size_t>(k * k));
    for (int lane = 0; lane < kLanes; ++lane) {
        assembleNormalMatrix(*sums, lane, 10, matrix.data());
        Eigen::MatrixXd design(f.samples, k);
        std::vector<double> basis(static_cast<std::size_t>(k));
        for (int s = 0; s < f.samples; ++s) {
            const auto a = f.anglesOf(s, lane).first;
            proto::fourierBasis(a.cosThetaD, a.cosThetaS, 10, basis.data());
            for (int j = 0; j < k; ++j) {
                design(s, j) = basis[static_cast<std::size_t>(j)];
            }
        }
        const Eigen::MatrixXd gram = design.transpose() * design;
        for (int i = 0; i < k; ++i) {
            for (int j = 0; j < k; ++j) {
                ASSERT_NEAR(matrix[static_cast<std::size_t>(i * k + j)], gram(i, j),
                            2e-5 * f.samples)
                    << "lane " << lane << " entry " << i << "," << j;
            }
        }
    }
}

TEST_P(NormalEquations, FastAndExactMatchTheNaiveFitWhenRegularized) {
    const KernelFixture f(10, dome(), 0.4, 0.01, 2);
    const auto fast = f.solve(3.14, AccumulationPrecision::kFloatBlocks);
    const auto exact = f.solve(3.14, AccumulationPrecision::kDouble);
    for (int lane = 0; lane < kLanes; ++lane) {
        const NaiveFitResult naive = f.naive(lane, 3.14);
        ASSERT_TRUE(naive.valid);
        ASSERT_TRUE(fast->valid[lane]);
        ASSERT_TRUE(exact->valid[lane]);
        for (int c = 0; c < 3; ++c) {
            for (int j = 0; j < proto::coefficientCount(10); ++j) {
                EXPECT_NEAR(fast->coefficients[lane][c][j], naive.coefficients(j, c), 2e-5);
                EXPECT_NEAR(exact->coefficients[lane][c][j], naive.coefficients(j, c), 1e-6);
            }
        }
    }
}

TEST_P(NormalEquations, NoiselessDataFromKnownCoefficientsIsRecovered) {
    // λ = 0 over lights on the whole sphere: the system is exact, and the recovery is limited
    // only by the conditioning of the basis, which grows fast with M (cos mθ and sin mθ both
    // span functions on [0, π]); M = 4 keeps it well within 1e-5.
    const int m = 4;
    const KernelFixture f(m, testing::sphereLights(120), 0.6, 0.0, 3);
    const auto exact = f.solve(0.0, AccumulationPrecision::kDouble);
    for (int lane = 0; lane < kLanes; ++lane) {
        ASSERT_TRUE(exact->valid[lane]);
        for (int c = 0; c < 3; ++c) {
            for (int j = 0; j < proto::coefficientCount(m); ++j) {
                EXPECT_NEAR(exact->coefficients[lane][c][j],
                            f.truth[(lane * 3 + c) * proto::coefficientCount(m) + j], 1e-5)
                    << "lane " << lane << " c " << c << " j " << j;
            }
        }
    }
}

TEST_P(NormalEquations, PointLightsNormalizeByInverseSquareDistance) {
    const KernelFixture f(3, testing::sphereLights(80), 0.5, 0.0, 4, /*pointLights=*/true);
    const auto exact = f.solve(0.0, AccumulationPrecision::kDouble);
    for (int lane = 0; lane < kLanes; ++lane) {
        ASSERT_TRUE(exact->valid[lane]);
        for (int j = 0; j < proto::coefficientCount(3); ++j) {
            EXPECT_NEAR(exact->coefficients[lane][1][j],
                        f.truth[(lane * 3 + 1) * proto::coefficientCount(3) + j], 1e-5);
        }
    }
}

TEST_P(NormalEquations, HugeLambdaDrivesEveryHarmonicToZero) {
    const KernelFixture f(10, dome(), 0.4, 0.01, 5);
    const auto solution = f.solve(1e12, AccumulationPrecision::kDouble);
    for (int lane = 0; lane < kLanes; ++lane) {
        ASSERT_TRUE(solution->valid[lane]);
        for (int c = 0; c < 3; ++c) {
            for (int j = 2; j < proto::coefficientCount(10); ++j) {
                EXPECT_LT(std::fabs(solution->coefficients[lane][c][j]), 1e-8);
            }
            // What remains is the diffuse fit, which is not penalized.
            EXPECT_GT(std::fabs(solution->coefficients[lane][c][proto::kLambertIndex]) +
                          std::fabs(solution->coefficients[lane][c][proto::kConstantIndex]),
                      1e-4);
        }
    }
}

TEST_P(NormalEquations, ZeroWeightSamplesAreIgnored) {
    KernelFixture f(5, dome(), 0.3, 0.01, 6);
    // Corrupt every third sample, then drop it: the fit must equal the naive fit without it.
    for (int s = 0; s < f.samples; s += 3) {
        for (int lane = 0; lane < kLanes; ++lane) {
            f.weights[static_cast<std::size_t>(s) * kLanes + lane] = 0.0f;
            for (int c = 0; c < 3; ++c) {
                f.values[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane] = 1e6f;
            }
        }
    }
    const auto solution = f.solve(1.0, AccumulationPrecision::kDouble);
    for (int lane = 0; lane < kLanes; ++lane) {
        const NaiveFitResult naive = f.naive(lane, 1.0);
        for (int j = 0; j < proto::coefficientCount(5); ++j) {
            EXPECT_NEAR(solution->coefficients[lane][0][j], naive.coefficients(j, 0), 1e-7);
        }
    }
}

TEST_P(NormalEquations, TooFewSamplesMarkTheLaneInvalidNotNaN) {
    KernelFixture f(10, dome(), 0.3, 0.0, 7);
    for (int s = 5; s < f.samples; ++s) {
        f.weights[static_cast<std::size_t>(s) * kLanes] = 0.0f;  // lane 0 keeps 5 samples
    }
    const auto solution = f.solve(3.14, AccumulationPrecision::kFloatBlocks);
    EXPECT_FALSE(solution->valid[0]);
    EXPECT_TRUE(solution->valid[1]);
    for (int c = 0; c < 3; ++c) {
        for (int j = 0; j < kMaxCoefficients; ++j) {
            EXPECT_EQ(solution->coefficients[0][c][j], 0.0f);
        }
        EXPECT_EQ(solution->rms[0][c], 0.0f);
    }
}

TEST_P(NormalEquations, ResidualRmsMatchesDirectComputation) {
    const KernelFixture f(6, dome(), 0.4, 0.02, 8);
    const auto solution = f.solve(2.0, AccumulationPrecision::kDouble);
    const int k = proto::coefficientCount(6);
    for (int lane = 0; lane < kLanes; ++lane) {
        double squares = 0;
        for (int s = 0; s < f.samples; ++s) {
            const auto a = f.anglesOf(s, lane).first;
            const double predicted = proto::evaluateFourierBrdf(solution->coefficients[lane][2], 6,
                                                                a.cosThetaD, a.cosThetaS);
            const double r =
                f.values[(static_cast<std::size_t>(s) * 3 + 2) * kLanes + lane] - predicted;
            squares += r * r;
        }
        EXPECT_NEAR(solution->rms[lane][2], std::sqrt(squares / f.samples), 1e-6);
        (void)k;
    }
}

}  // namespace
}  // namespace vpe::fit
