// SPDX-License-Identifier: MIT
// principalAxes: order, sign, selection and degenerate sets, on samples whose axes are known.
#include "vpe/common/principal_axes.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace vpe {
namespace {

// 4-d samples around (1, 2, 3, 4) with standard deviations 3, 2, 0.5 and 0 along a rotated
// frame: the true axes are the frame's columns, largest variance first.
struct KnownSet {
    std::vector<float> values;
    Eigen::Matrix4d frame = Eigen::Matrix4d::Zero();
    std::size_t count = 20000;

    const float* at(std::size_t i) const { return &values[4 * i]; }
};

KnownSet knownSet() {
    KnownSet set;
    set.frame.block<3, 3>(0, 0) =
        Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    set.frame(3, 3) = 1;
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    const Eigen::Vector4d sigma(3, 2, 0.5, 0), mean(1, 2, 3, 4);
    for (std::size_t i = 0; i < set.count; ++i) {
        Eigen::Vector4d z;
        for (int k = 0; k < 4; ++k) {
            z[k] = sigma[k] * normal(random);
        }
        const Eigen::Vector4d x = mean + set.frame * z;
        for (int k = 0; k < 4; ++k) {
            set.values.push_back(static_cast<float>(x[k]));
        }
    }
    return set;
}

TEST(PrincipalAxes, FindsTheAxesInOrderWithTheirVariances) {
    const KnownSet set = knownSet();
    const common::PrincipalAxes pca =
        common::principalAxes(set.count, 4, [&](std::size_t i) { return set.at(i); });
    ASSERT_EQ(pca.count(), 4);
    EXPECT_EQ(pca.samples, set.count);
    EXPECT_NEAR(pca.mean[0], 1.0, 0.05);
    EXPECT_NEAR(pca.mean[3], 4.0, 1e-5);
    const double expected[4] = {9, 4, 0.25, 0};
    for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(pca.variances[k], expected[k], 0.04 * expected[k] + 1e-6) << k;
    }
    for (int k = 0; k < 3; ++k) {
        // The same line as the true axis (either sign), to sampling accuracy.
        EXPECT_GT(std::abs(pca.axes.col(k).dot(set.frame.col(k))), 0.995) << k;
    }
    EXPECT_NEAR(pca.totalVariance, 13.25, 0.3);
    EXPECT_NEAR(pca.explained(), 1.0, 1e-12);
}

TEST(PrincipalAxes, EachAxisHasItsLargestEntryPositive) {
    const KnownSet set = knownSet();
    const common::PrincipalAxes pca =
        common::principalAxes(set.count, 4, [&](std::size_t i) { return set.at(i); });
    for (int k = 0; k < pca.count(); ++k) {
        Eigen::Index largest = 0;
        pca.axes.col(k).cwiseAbs().maxCoeff(&largest);
        EXPECT_GT(pca.axes(largest, k), 0.0) << k;
        EXPECT_NEAR(pca.axes.col(k).norm(), 1.0, 1e-12) << k;
    }
}

TEST(PrincipalAxes, KeepsAsFewAxesAsTheSelectionAsks) {
    const KnownSet set = knownSet();
    const auto count = [&](common::AxisSelection selection) {
        return common::principalAxes(
                   set.count, 4, [&](std::size_t i) { return set.at(i); }, selection)
            .count();
    };
    EXPECT_EQ(count({.maxAxes = 2}), 2);
    // 9 / 13.25 = 68%, (9 + 4) / 13.25 = 98%.
    EXPECT_EQ(count({.varianceToKeep = 0.5}), 1);
    EXPECT_EQ(count({.varianceToKeep = 0.9}), 2);
    EXPECT_EQ(count({.varianceToKeep = 0.999}), 3);
    // The fourth axis has no variance: dropped when asked, kept when a rank is asked for.
    EXPECT_EQ(count({.dropBelow = 1e-9}), 3);
    EXPECT_EQ(count({.maxAxes = 4}), 4);
    const common::PrincipalAxes two = common::principalAxes(
        set.count, 4, [&](std::size_t i) { return set.at(i); }, {.maxAxes = 2});
    EXPECT_NEAR(two.explained(), 13.0 / 13.25, 0.01);
}

TEST(PrincipalAxes, ASetWithoutVarianceStillGivesTheAxesAskedFor) {
    const std::vector<float> same(3 * 10, 0.5f);
    const auto at = [&](std::size_t i) { return &same[3 * i]; };
    const common::PrincipalAxes ranked = common::principalAxes(10, 3, at, {.maxAxes = 2});
    EXPECT_EQ(ranked.count(), 2);
    EXPECT_EQ(ranked.totalVariance, 0.0);
    EXPECT_EQ(ranked.explained(), 0.0);
    EXPECT_NEAR(ranked.mean[1], 0.5, 1e-7);
    EXPECT_EQ(common::principalAxes(10, 3, at, {.dropBelow = 1e-12}).count(), 0);
    EXPECT_EQ(common::principalAxes(0, 3, at, {.maxAxes = 3}).samples, 0u);
}

}  // namespace
}  // namespace vpe
