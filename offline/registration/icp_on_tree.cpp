// SPDX-License-Identifier: MIT
// Point-to-plane ICP on a prebuilt KD tree: Open3D 0.16's RegistrationICP loop
// (pipelines/registration/Registration.cpp) without its per-call tree build. The
// correspondences are gathered in source order, so the result does not depend on the threads.
#include "icp_on_tree.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <open3d/pipelines/registration/TransformationEstimation.h>

#include "vpe/common/parallel_for.h"

namespace vpe::registration {

namespace {

namespace o3d = open3d;
namespace reg = open3d::pipelines::registration;

// Each moved point's nearest target point within maxDistance, and the fit's fitness and inlier
// RMSE (Euclidean), as Open3D's GetRegistrationResultAndCorrespondences computes them.
reg::RegistrationResult correspondencesOf(const o3d::geometry::PointCloud& moved,
                                          const o3d::geometry::KDTreeFlann& targetTree,
                                          double maxDistance, const Eigen::Matrix4d& transformation,
                                          unsigned threads) {
    const std::size_t count = moved.points_.size();
    std::vector<int> nearest(count, -1);
    std::vector<double> squared(count, 0);
    common::parallelFor(count, 2048, threads, [&](std::size_t begin, std::size_t end) {
        std::vector<int> index(1);
        std::vector<double> distance2(1);
        for (std::size_t i = begin; i < end; ++i) {
            if (targetTree.SearchHybrid(moved.points_[i], maxDistance, 1, index, distance2) > 0) {
                nearest[i] = index[0];
                squared[i] = distance2[0];
            }
        }
    });
    reg::RegistrationResult result(transformation);
    double error2 = 0;
    for (std::size_t i = 0; i < count; ++i) {
        if (nearest[i] >= 0) {
            result.correspondence_set_.emplace_back(static_cast<int>(i), nearest[i]);
            error2 += squared[i];
        }
    }
    const std::size_t inliers = result.correspondence_set_.size();
    if (inliers > 0) {
        result.fitness_ = double(inliers) / double(count);
        result.inlier_rmse_ = std::sqrt(error2 / double(inliers));
    }
    return result;
}

}  // namespace

reg::RegistrationResult icpOnTree(const o3d::geometry::PointCloud& source,
                                  const o3d::geometry::PointCloud& target,
                                  const o3d::geometry::KDTreeFlann& targetTree, double maxDistance,
                                  const Eigen::Matrix4d& init,
                                  const reg::ICPConvergenceCriteria& criteria, unsigned threads) {
    if (!(maxDistance > 0) || !target.HasNormals()) {
        throw std::invalid_argument("icpOnTree: needs a positive distance and target normals");
    }
    const reg::TransformationEstimationPointToPlane estimation;
    // Only the points move: point-to-plane reads the target's normals, not the source's.
    o3d::geometry::PointCloud moved;
    moved.points_ = source.points_;
    Eigen::Matrix4d transformation = init;
    if (!init.isIdentity()) {
        moved.Transform(init);
    }
    reg::RegistrationResult result =
        correspondencesOf(moved, targetTree, maxDistance, transformation, threads);
    for (int i = 0; i < criteria.max_iteration_; ++i) {
        const Eigen::Matrix4d update =
            estimation.ComputeTransformation(moved, target, result.correspondence_set_);
        transformation = update * transformation;
        moved.Transform(update);
        const double fitness = result.fitness_, rmse = result.inlier_rmse_;
        result = correspondencesOf(moved, targetTree, maxDistance, transformation, threads);
        if (std::abs(fitness - result.fitness_) < criteria.relative_fitness_ &&
            std::abs(rmse - result.inlier_rmse_) < criteria.relative_rmse_) {
            break;
        }
    }
    return result;
}

}  // namespace vpe::registration
