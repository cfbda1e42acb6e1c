// SPDX-License-Identifier: MIT
// The extended fit's lane kernels against each lane's own computation in plain double (Eigen
// for the solves, a refit per left-out light for PRESS), on every SIMD target the kernels are
// compiled for and this CPU runs.
#include "vpe/fit/extended_lane_kernels.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/luminance.h"

#include "support/synthetic_capture.h"

namespace vpe::fit {
namespace {

constexpr int kTerms = model::kTransportTerms;
constexpr int kPairs = ExtendedLightTable::kTransportPairs;
using Matrix = Eigen::Matrix<double, kTerms, kTerms>;
using Vector = Eigen::Matrix<double, kTerms, 1>;

std::size_t at(int entry, int lane) {
    return static_cast<std::size_t>(entry) * kLanes + static_cast<std::size_t>(lane);
}

// A dome of lights and, per sample and lane, the luminance T fit's inputs: weight w, the BRDF's
// prediction P and the observation L (a shading T times P, plus noise).
struct LaneFixture {
    capture::Capture capture;
    std::unique_ptr<ExtendedLightTable> table;
    int samples = 0;
    std::vector<double> weight, predicted, observed;  // [sample][lane]
    std::vector<double> u, v;                         // w P², w P L: [sample][lane]

    explicit LaneFixture(std::uint32_t seed) {
        for (const proto::Vec3d& d : testing::domeLights({15, 35, 55, 75}, 10)) {
            capture.images.push_back({"", {d.x, d.y, d.z}, 1.0, 0});
        }
        table = std::make_unique<ExtendedLightTable>(capture);
        samples = static_cast<int>(capture.images.size());
        std::mt19937 random(seed);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        const std::size_t size = static_cast<std::size_t>(samples) * kLanes;
        weight.resize(size);
        predicted.resize(size);
        observed.resize(size);
        u.resize(size);
        v.resize(size);
        for (int s = 0; s < samples; ++s) {
            for (int lane = 0; lane < kLanes; ++lane) {
                const std::size_t i = at(s, lane);
                weight[i] = uniform(random) < 0.1 ? 0.0 : 0.5 + uniform(random);
                predicted[i] = 0.2 + uniform(random);
                const double shading = 0.3 + 0.7 * capture.images[s].light.z;
                observed[i] = shading * predicted[i] + 0.02 * (uniform(random) - 0.5);
                u[i] = weight[i] * predicted[i] * predicted[i];
                v[i] = weight[i] * predicted[i] * observed[i];
            }
        }
    }

    // One lane's A and b, summed sample by sample.
    std::pair<Matrix, Vector> equations(int lane, int leftOut = -1) const {
        Matrix a = Matrix::Zero();
        Vector b = Vector::Zero();
        for (int s = 0; s < samples; ++s) {
            if (s == leftOut) {
                continue;
            }
            const Eigen::Map<const Vector> h(table->transportBasis[s].data());
            a += u[at(s, lane)] * h * h.transpose();
            b += v[at(s, lane)] * h;
        }
        return {a, b};
    }
};

class ExtendedLaneKernels : public ::testing::TestWithParam<std::int64_t> {
protected:
    void SetUp() override {
        hwy::SetSupportedTargetsForTest(GetParam());
        ASSERT_EQ(activeKernelTarget(), GetParam()) << "the kernels did not switch target";
    }
    void TearDown() override { hwy::SetSupportedTargetsForTest(0); }
};

INSTANTIATE_TEST_SUITE_P(FitKernelTargets, ExtendedLaneKernels,
                         ::testing::ValuesIn(kernelTargets()),
                         [](const ::testing::TestParamInfo<std::int64_t>& target) {
                             return std::string(hwy::TargetName(target.param));
                         });

TEST_P(ExtendedLaneKernels, TransportSumsAreEachLanesOwnSums) {
    const LaneFixture f(1);
    std::vector<double> pairs(kPairs * kLanes), rights(kTerms * kLanes);
    sumTransportEquations(*f.table, f.samples, 1, f.u.data(), f.v.data(), pairs.data(),
                          rights.data());
    for (int lane = 0; lane < kLanes; ++lane) {
        const auto [a, b] = f.equations(lane);
        for (int row = 0, k = 0; row < kTerms; ++row) {
            for (int column = row; column < kTerms; ++column, ++k) {
                EXPECT_NEAR(pairs[at(k, lane)], a(row, column), 1e-12 * a.norm()) << lane;
            }
            EXPECT_NEAR(rights[at(row, lane)], b[row], 1e-12 * b.norm()) << lane;
        }
    }
}

TEST_P(ExtendedLaneKernels, RidgeSolvesMatchEachLanesLlt) {
    const LaneFixture f(2);
    std::vector<double> pairs(kPairs * kLanes), rights(kTerms * kLanes);
    sumTransportEquations(*f.table, f.samples, 1, f.u.data(), f.v.data(), pairs.data(),
                          rights.data());
    double pull[kLanes];
    std::vector<double> prior(kTerms * kLanes), t(kTerms * kLanes);
    for (int lane = 0; lane < kLanes; ++lane) {
        pull[lane] = 0.01 * (lane + 1);
        for (int k = 0; k < kTerms; ++k) {
            prior[at(k, lane)] = k == 0 ? 3.5 : 0.01 * (k - lane);
        }
    }
    // Lane 5 has no samples and no ridge: its Cholesky fails, and says so.
    for (int k = 0; k < kPairs; ++k) {
        pairs[at(k, 5)] = 0.0;
    }
    pull[5] = 0.0;
    bool solved[kLanes];
    solveTransportLanes(pairs.data(), rights.data(), pull, prior.data(), t.data(), solved);
    for (int lane = 0; lane < kLanes; ++lane) {
        if (lane == 5) {
            EXPECT_FALSE(solved[lane]);
            continue;
        }
        ASSERT_TRUE(solved[lane]) << lane;
        auto [a, b] = f.equations(lane);
        Vector p;
        for (int k = 0; k < kTerms; ++k) {
            p[k] = prior[at(k, lane)];
        }
        a.diagonal().array() += pull[lane];
        const Vector expected = a.llt().solve(b + pull[lane] * p);
        for (int k = 0; k < kTerms; ++k) {
            EXPECT_NEAR(t[at(k, lane)], expected[k], 1e-9 * expected.norm()) << lane << " " << k;
        }
    }
}

// PRESS in closed form equals the error of refitting without each light in turn.
TEST_P(ExtendedLaneKernels, PressIsTheErrorOfLeavingEachLightOut) {
    const LaneFixture f(3);
    std::vector<double> pairs(kPairs * kLanes), rights(kTerms * kLanes);
    sumTransportEquations(*f.table, f.samples, 1, f.u.data(), f.v.data(), pairs.data(),
                          rights.data());
    double pull[kLanes];
    std::vector<double> prior(kTerms * kLanes, 0.0);
    for (int lane = 0; lane < kLanes; ++lane) {
        pull[lane] = 0.05 + 0.02 * lane;
        prior[at(0, lane)] = 3.5;
    }
    const LanePressSamples samples{f.samples, f.weight.data(), f.predicted.data(),
                                   f.observed.data()};
    double press[kLanes];
    bool valid[kLanes];
    transportPressLanes(*f.table, pairs.data(), rights.data(), pull, prior.data(), samples, press,
                        valid);
    for (int lane = 0; lane < kLanes; ++lane) {
        ASSERT_TRUE(valid[lane]) << lane;
        double expected = 0;
        for (int s = 0; s < f.samples; ++s) {
            const double w = f.weight[at(s, lane)];
            if (w <= 0) {
                continue;
            }
            auto [a, b] = f.equations(lane, s);
            a.diagonal().array() += pull[lane];
            Vector p = Vector::Zero();
            p[0] = 3.5;
            const Vector t = a.llt().solve(b + pull[lane] * p);
            const Eigen::Map<const Vector> h(f.table->transportBasis[s].data());
            const double residual = f.observed[at(s, lane)] - f.predicted[at(s, lane)] * h.dot(t);
            expected += w * residual * residual;
        }
        EXPECT_NEAR(press[lane], expected, 1e-8 * expected) << lane;
    }
}

TEST_P(ExtendedLaneKernels, SampledTransportIsTheBoundedSeries) {
    const LaneFixture f(4);
    std::vector<double> t(kTerms * kLanes);
    std::mt19937 random(4);
    std::normal_distribution<double> gaussian(0.0, 2.0);
    for (double& value : t) {
        value = gaussian(random);
    }
    std::vector<float> sampled(static_cast<std::size_t>(f.samples) * kLanes);
    sampleTransportLanes(*f.table, t.data(), f.samples, sampled.data());
    int bounded = 0;
    for (int s = 0; s < f.samples; ++s) {
        for (int lane = 0; lane < kLanes; ++lane) {
            double sum = 0;
            for (int k = 0; k < kTerms; ++k) {
                sum += t[at(k, lane)] * f.table->transportBasis[s][k];
            }
            bounded += sum < 0 || sum > 4 ? 1 : 0;
            EXPECT_NEAR(sampled[at(s, lane)], std::min(std::max(sum, 0.0), 4.0), 1e-5);
        }
    }
    EXPECT_GT(bounded, 0) << "the bounds were not tested";
}

// A chunk's BRDFs and samples for the prediction and error kernels.
struct BrdfFixture {
    static constexpr int kHarmonics = 6;
    int samples = 40;
    std::unique_ptr<ChunkSolution> brdf = std::make_unique<ChunkSolution>();
    std::vector<double> cosD, cosS, irradiance;  // [sample][lane]
    std::vector<float> weights, values, transport;
    std::vector<std::uint8_t> saturated;

    BrdfFixture() {
        std::mt19937 random(5);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        for (int lane = 0; lane < kLanes; ++lane) {
            for (int c = 0; c < kChannels; ++c) {
                for (int k = 0; k < proto::coefficientCount(kHarmonics); ++k) {
                    brdf->coefficients[lane][c][k] = static_cast<float>(uniform(random) - 0.3);
                }
            }
        }
        const std::size_t size = static_cast<std::size_t>(samples) * kLanes;
        for (std::size_t i = 0; i < size; ++i) {
            cosD.push_back(2 * uniform(random) - 0.5);
            cosS.push_back(2 * uniform(random) - 1);
            irradiance.push_back(0.5 + uniform(random));
            weights.push_back(uniform(random) < 0.2 ? 0.0f : static_cast<float>(uniform(random)));
            saturated.push_back(uniform(random) < 0.3 ? 1 : 0);
        }
        for (std::size_t i = 0; i < size * 3; ++i) {
            values.push_back(static_cast<float>(uniform(random)));
            transport.push_back(static_cast<float>(0.2 + uniform(random)));
        }
    }

    LaneSamples laneSamples() const {
        return {samples, cosD.data(), cosS.data(), irradiance.data()};
    }

    // f of sample s at a lane, one lane alone.
    void evaluate(int s, int lane, double (&rgb)[3]) const {
        double coefficients[kChannels][kMaxCoefficients] = {};
        for (int c = 0; c < kChannels; ++c) {
            for (int k = 0; k < proto::coefficientCount(kHarmonics); ++k) {
                coefficients[c][k] = brdf->coefficients[lane][c][k];
            }
        }
        proto::evaluateFourierBrdfRgb(&coefficients[0][0], kMaxCoefficients, kHarmonics,
                                      cosD[at(s, lane)], cosS[at(s, lane)], rgb);
    }
};

TEST_P(ExtendedLaneKernels, PredictionsAreEachLanesOwn) {
    const BrdfFixture f;
    std::vector<double> rgb(static_cast<std::size_t>(f.samples) * 3 * kLanes);
    std::vector<double> luminance(static_cast<std::size_t>(f.samples) * kLanes);
    predictEveryLane(*f.brdf, BrdfFixture::kHarmonics, f.laneSamples(), rgb.data(),
                     luminance.data());
    for (int s = 0; s < f.samples; ++s) {
        for (int lane = 0; lane < kLanes; ++lane) {
            double expected[3];
            f.evaluate(s, lane, expected);
            double y = 0;
            for (int c = 0; c < 3; ++c) {
                expected[c] *= f.irradiance[at(s, lane)];
                EXPECT_NEAR(rgb[at(s * 3 + c, lane)], expected[c], 1e-12) << s << " " << lane;
                y += proto::kLuminance709[c] * expected[c];
            }
            EXPECT_NEAR(luminance[at(s, lane)], y, 1e-12) << s << " " << lane;
        }
    }
}

TEST_P(ExtendedLaneKernels, TrainingErrorSkipsUnweightedAndReachedClippedSamples) {
    const BrdfFixture f;
    const LaneObservations observed{f.weights.data(), f.saturated.data(), f.values.data(),
                                    f.transport.data()};
    double error[kLanes];
    everyLaneError(*f.brdf, BrdfFixture::kHarmonics, f.laneSamples(), observed, error);
    for (int lane = 0; lane < kLanes; ++lane) {
        double expected = 0;
        for (int s = 0; s < f.samples; ++s) {
            double rgb[3];
            f.evaluate(s, lane, rgb);
            const double w = f.weights[at(s, lane)];
            for (int c = 0; c < 3; ++c) {
                const double model =
                    f.transport[at(s * 3 + c, lane)] * f.irradiance[at(s, lane)] * rgb[c];
                const double y = f.values[at(s * 3 + c, lane)];
                if (w <= 0 || (f.saturated[at(s, lane)] && model >= y)) {
                    continue;
                }
                expected += w * (y - model) * (y - model);
            }
        }
        EXPECT_NEAR(error[lane], expected, 1e-12 * (1 + expected)) << lane;
    }
}

}  // namespace
}  // namespace vpe::fit
