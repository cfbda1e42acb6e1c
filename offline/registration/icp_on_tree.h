// SPDX-License-Identifier: MIT
// Point-to-plane ICP against a target whose KD tree is already built (private to
// registration/). Open3D's RegistrationICP builds its target's tree on every call; the fine fit
// and the turn search call ICP some forty times against the same dense mesh cloud of up to two
// million points, and rebuilding that tree was a quarter of registration's time.
#pragma once

#include <Eigen/Core>
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>

namespace vpe::registration {

// Open3D's RegistrationICP with TransformationEstimationPointToPlane, on `targetTree` (built on
// `target`, which must have normals): the same correspondences (each source point's nearest
// target point within maxDistance), fitness, inlier RMSE and stopping rule (both changes below
// the criteria, or max_iteration_ steps). The searches run on `threads` threads; the result
// does not depend on their number.
open3d::pipelines::registration::RegistrationResult icpOnTree(
    const open3d::geometry::PointCloud& source, const open3d::geometry::PointCloud& target,
    const open3d::geometry::KDTreeFlann& targetTree, double maxDistance,
    const Eigen::Matrix4d& init,
    const open3d::pipelines::registration::ICPConvergenceCriteria& criteria, unsigned threads);

}  // namespace vpe::registration
