// SPDX-License-Identifier: MIT
// Mesh-to-scan registration with Open3D: FPFH + RANSAC, point-to-plane ICP, and the degeneracy
// of the final fit (Gelfand et al., "Geometrically stable sampling for the ICP algorithm", 2003:
// the eigenvectors of the point-to-plane information matrix).
#include "vpe/registration/mesh_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Dense>
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/pipelines/registration/CorrespondenceChecker.h>
#include <open3d/pipelines/registration/Feature.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/utility/Random.h>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"

#include "icp_on_tree.h"

namespace vpe::registration {

namespace {

namespace o3d = open3d;
namespace reg = open3d::pipelines::registration;
constexpr double kPi = 3.14159265358979323846;
// Correspondences within this distance (metres) count as inliers of the final fit.
constexpr double kInlierDistance = 0.001;
// Mesh samples per square metre for the fine fit: one every 0.5 mm.
constexpr double kMeshDensity = 4e6;
constexpr std::size_t kMaxFineScanPoints = 60000;
// A global candidate whose ICP on the thinned clouds puts this share of the scan within two
// voxels of the mesh is taken without more trials.
constexpr double kGoodCoarseFit = 0.95;
// The turn search's points: every so many of the fine fit's.
constexpr std::size_t kSearchStride = 12;

Eigen::Matrix4d matrixOf(const Pose& pose) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            m(i, j) = pose.R[static_cast<std::size_t>(3 * i + j)];
        }
        m(i, 3) = pose.t[static_cast<std::size_t>(i)];
    }
    return m;
}

Pose poseOf(const Eigen::Matrix4d& m) {
    Pose pose;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            pose.R[static_cast<std::size_t>(3 * i + j)] = m(i, j);
        }
        pose.t[static_cast<std::size_t>(i)] = m(i, 3);
    }
    return pose;
}

Eigen::Vector3d eigen(const std::array<double, 3>& v) {
    return {v[0], v[1], v[2]};
}

// The fit's quality: inlier share and point-to-plane RMS, and the inliers themselves (object
// frame) with the mesh's normals there, for the degeneracy test.
struct FitQuality {
    double inlierShare = 0, rms = 0;
    std::vector<std::array<double, 3>> points, normals;
};

FitQuality measureFit(const o3d::geometry::PointCloud& scan, const o3d::geometry::PointCloud& mesh,
                      const o3d::geometry::KDTreeFlann& tree,
                      const Eigen::Matrix4d& cameraToObject) {
    FitQuality quality;
    double squares = 0;
    std::vector<int> index(1);
    std::vector<double> distance(1);
    for (const Eigen::Vector3d& point : scan.points_) {
        const Eigen::Vector3d p =
            cameraToObject.block<3, 3>(0, 0) * point + cameraToObject.block<3, 1>(0, 3);
        if (tree.SearchKNN(p, 1, index, distance) < 1 ||
            distance[0] > kInlierDistance * kInlierDistance) {
            continue;
        }
        const Eigen::Vector3d& n = mesh.normals_[static_cast<std::size_t>(index[0])];
        const double r = n.dot(p - mesh.points_[static_cast<std::size_t>(index[0])]);
        squares += r * r;
        quality.points.push_back({p.x(), p.y(), p.z()});
        quality.normals.push_back({n.x(), n.y(), n.z()});
    }
    const std::size_t inliers = quality.points.size();
    quality.inlierShare = scan.points_.empty() ? 0 : double(inliers) / double(scan.points_.size());
    quality.rms =
        inliers ? std::sqrt(squares / double(inliers)) : std::numeric_limits<double>::infinity();
    return quality;
}

}  // namespace

Pose faceTowards(const Pose& pose, const std::array<double, 3>& axisIn,
                 const std::array<double, 3>& axisPoint, const proto::Vec3d& target,
                 double* turnDeg) {
    const Eigen::Matrix4d m = matrixOf(pose);
    const Eigen::Matrix3d R = m.block<3, 3>(0, 0);
    const Eigen::Vector3d t = m.block<3, 1>(0, 3);
    const Eigen::Vector3d a = eigen(axisIn).normalized(), c = eigen(axisPoint);
    // The target in the object's frame, and both directions across the axis.
    const Eigen::Vector3d local =
        R.transpose() * (Eigen::Vector3d(target.x, target.y, target.z) - t);
    Eigen::Vector3d towards = local - c;
    towards -= towards.dot(a) * a;
    Eigen::Vector3d front(0, 0, 1);
    front -= front.dot(a) * a;
    if (towards.norm() < 1e-9 || front.norm() < 1e-9) {
        if (turnDeg != nullptr) {
            *turnDeg = 0;
        }
        return pose;  // the target sits on the axis, or the axis is the front: nothing to turn
    }
    const double angle = std::atan2(a.dot(front.cross(towards)), front.dot(towards));
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle, a).toRotationMatrix();
    Eigen::Matrix4d out = Eigen::Matrix4d::Identity();
    out.block<3, 3>(0, 0) = R * turn;
    out.block<3, 1>(0, 3) = t + R * (c - turn * c);
    if (turnDeg != nullptr) {
        *turnDeg = angle * 180 / kPi;
    }
    return poseOf(out);
}

namespace {

// The point-to-plane information matrix about the points' centroid, rotations scaled by their
// RMS radius, its eigen-decomposition, and that centre and radius.
struct Information {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 1;
};

Information informationOf(const std::vector<std::array<double, 3>>& points,
                          const std::vector<std::array<double, 3>>& normals) {
    Information info;
    for (const auto& p : points) {
        info.centre += eigen(p);
    }
    info.centre /= double(points.size());
    double radius = 0;
    for (const auto& p : points) {
        radius += (eigen(p) - info.centre).squaredNorm();
    }
    info.radius = std::sqrt(radius / double(points.size()));
    Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d n = eigen(normals[i]);
        Eigen::Matrix<double, 6, 1> J;
        J.head<3>() = (eigen(points[i]) - info.centre).cross(n) / info.radius;
        J.tail<3>() = n;
        information += J * J.transpose();
    }
    info.solver.compute(information);
    return info;
}

// The eigenvector `index` as a turn: ω × (X − c_0) + v = ω × (X − c) with v = ω × (c_0 − c),
// refused (false) for a slide (ω ≈ 0) or a screw (v along ω).
bool asTurn(const Information& info, int index, std::array<double, 3>& axis,
            std::array<double, 3>& axisPoint) {
    const Eigen::Matrix<double, 6, 1> motion = info.solver.eigenvectors().col(index);
    const Eigen::Vector3d omega = motion.head<3>() / info.radius, velocity = motion.tail<3>();
    const double pitch = omega.dot(velocity) / omega.squaredNorm();
    if (motion.head<3>().norm() < 0.2 || std::abs(pitch) > 0.1 * info.radius) {
        return false;
    }
    const Eigen::Vector3d a = omega.normalized();
    const Eigen::Vector3d point = info.centre - velocity.cross(omega) / omega.squaredNorm();
    axis = {a.x(), a.y(), a.z()};
    axisPoint = {point.x(), point.y(), point.z()};
    return true;
}

}  // namespace

FreeMotions freeMotions(const std::vector<std::array<double, 3>>& points,
                        const std::vector<std::array<double, 3>>& normals, double maxShare) {
    FreeMotions free;
    if (points.empty()) {
        return free;
    }
    const Information info = informationOf(points, normals);
    const Eigen::Matrix<double, 6, 1> values = info.solver.eigenvalues();
    for (int i = 0; i < 6; ++i) {
        free.count += values(i) < maxShare * values(5) ? 1 : 0;
    }
    free.turn = free.count == 1 && asTurn(info, 0, free.axis, free.axisPoint);
    return free;
}

WeakestTurn weakestTurn(const std::vector<std::array<double, 3>>& points,
                        const std::vector<std::array<double, 3>>& normals) {
    WeakestTurn weakest;
    if (points.empty()) {
        return weakest;
    }
    const Information info = informationOf(points, normals);
    weakest.share = info.solver.eigenvalues()(0) / info.solver.eigenvalues()(5);
    weakest.turn = asTurn(info, 0, weakest.axis, weakest.axisPoint);
    return weakest;
}

proto::PinholeCamera inObjectFrame(const proto::PinholeCamera& device, const Pose& objectToCamera) {
    const Pose moved = compose(poseOfDevice(device), objectToCamera);
    proto::PinholeCamera out = device;
    out.R = moved.R;
    out.T = moved.t;
    return out;
}

Pose poseOfDevice(const proto::PinholeCamera& device) {
    return {device.R, device.T};
}

Pose compose(const Pose& outer, const Pose& inner) {
    return poseOf(matrixOf(outer) * matrixOf(inner));
}

Pose inverse(const Pose& pose) {
    return poseOf(matrixOf(pose).inverse());
}

double rotationDifferenceDeg(const Pose& a, const Pose& b) {
    const Eigen::Matrix3d d =
        matrixOf(a).block<3, 3>(0, 0) * matrixOf(b).block<3, 3>(0, 0).transpose();
    return std::acos(std::clamp((d.trace() - 1) / 2, -1.0, 1.0)) * 180 / kPi;
}

double originDistanceM(const Pose& a, const Pose& b) {
    return (eigen(a.t) - eigen(b.t)).norm();
}

RegistrationResult registerMesh(const scene::ScreenMesh& mesh,
                                const scan::ProjectorSurface& surface,
                                const proto::PinholeCamera& projector,
                                const RegistrationOptions& options) {
    // The scan, in the camera's frame.
    auto scan = std::make_shared<o3d::geometry::PointCloud>();
    const std::size_t pixels = static_cast<std::size_t>(surface.width) * surface.height;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (std::isnan(surface.position[3 * p]) || std::isnan(surface.normal[3 * p])) {
            continue;
        }
        scan->points_.emplace_back(surface.position[3 * p], surface.position[3 * p + 1],
                                   surface.position[3 * p + 2]);
        scan->normals_.emplace_back(surface.normal[3 * p], surface.normal[3 * p + 1],
                                    surface.normal[3 * p + 2]);
    }
    if (scan->points_.size() < 1000) {
        throw common::InputError("registration: the scan has " +
                                 std::to_string(scan->points_.size()) +
                                 " points; too few to place a mesh");
    }
    // The mesh, in its own frame, sampled densely with its interpolated normals.
    o3d::geometry::TriangleMesh triangles;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        triangles.vertices_.emplace_back(mesh.positions[i].x, mesh.positions[i].y,
                                         mesh.positions[i].z);
        triangles.vertex_normals_.emplace_back(mesh.normals[i].x, mesh.normals[i].y,
                                               mesh.normals[i].z);
    }
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        triangles.triangles_.emplace_back(mesh.indices[t], mesh.indices[t + 1],
                                          mesh.indices[t + 2]);
    }
    o3d::utility::random::Seed(static_cast<int>(options.seed));
    const double area = triangles.GetSurfaceArea();
    const auto samples = static_cast<std::size_t>(std::clamp(area * kMeshDensity, 20000.0, 2e6));
    const std::shared_ptr<o3d::geometry::PointCloud> dense =
        triangles.SamplePointsUniformly(samples);
    const o3d::geometry::KDTreeFlann denseTree(*dense);

    // The global alignment, on both clouds thinned to the voxel.
    const double voxel = options.voxelM;
    const auto scanCoarse = scan->VoxelDownSample(voxel);
    const auto meshCoarse = dense->VoxelDownSample(voxel);
    const o3d::geometry::KDTreeSearchParamHybrid featureSearch(5 * voxel, 100);
    const auto scanFeatures = reg::ComputeFPFHFeature(*scanCoarse, featureSearch);
    const auto meshFeatures = reg::ComputeFPFHFeature(*meshCoarse, featureSearch);
    const reg::CorrespondenceCheckerBasedOnEdgeLength edges(0.9);
    const reg::CorrespondenceCheckerBasedOnDistance distance(1.5 * voxel);
    // The fine fit uses at most kMaxFineScanPoints of the scan, spread evenly.
    o3d::geometry::PointCloud fine;
    const std::size_t stride = std::max<std::size_t>(1, scan->points_.size() / kMaxFineScanPoints);
    for (std::size_t i = 0; i < scan->points_.size(); i += stride) {
        fine.points_.push_back(scan->points_[i]);
        fine.normals_.push_back(scan->normals_[i]);
    }

    // Global candidates, each refined on the thinned clouds; the best one refined on all.
    Eigen::Matrix4d best = Eigen::Matrix4d::Identity();
    double bestScore = -1;
    for (int trial = 0; trial < options.globalTrials; ++trial) {
        o3d::utility::random::Seed(static_cast<int>(options.seed) + 7919 * trial);
        const reg::RegistrationResult global = reg::RegistrationRANSACBasedOnFeatureMatching(
            *scanCoarse, *meshCoarse, *scanFeatures, *meshFeatures, true, 1.5 * voxel,
            reg::TransformationEstimationPointToPoint(false), 3, {edges, distance},
            reg::RANSACConvergenceCriteria(options.ransacIterations, 0.999));
        const reg::RegistrationResult coarse =
            reg::RegistrationICP(*scanCoarse, *meshCoarse, 2 * voxel, global.transformation_,
                                 reg::TransformationEstimationPointToPlane(),
                                 reg::ICPConvergenceCriteria(1e-7, 1e-7, 60));
        // Inliers first (the right place), then the residual, in units of the voxel.
        const double score = coarse.fitness_ - coarse.inlier_rmse_ / voxel * 0.01;
        if (score > bestScore) {
            bestScore = score;
            best = coarse.transformation_;
        }
        if (coarse.fitness_ > kGoodCoarseFit) {
            break;  // nearly every scan point on the mesh: further trials only cost time
        }
    }
    // ICP from a start, at decreasing distances, on `points` (all of `fine`, or a sparse of them
    // while searching), on the dense cloud's one tree.
    const unsigned threads = common::resolveThreadCount(static_cast<int>(options.threads));
    const auto refine = [&](const o3d::geometry::PointCloud& points, const Eigen::Matrix4d& start,
                            int iterations) {
        Eigen::Matrix4d transformation = start;
        for (const double threshold :
             {2 * kInlierDistance, kInlierDistance, 0.5 * kInlierDistance}) {
            transformation = icpOnTree(points, *dense, denseTree, threshold, transformation,
                                       reg::ICPConvergenceCriteria(1e-9, 1e-9, iterations), threads)
                                 .transformation_;
        }
        return transformation;
    };
    // Inliers first (the right place: a lug out of place is a patch of outliers), then the
    // point-to-plane residual.
    const auto score = [&](const o3d::geometry::PointCloud& points, const Eigen::Matrix4d& t) {
        const FitQuality q = measureFit(points, *dense, denseTree, t);
        return q.inlierShare - 0.01 * q.rms / kInlierDistance;
    };
    best = refine(fine, best, 40);
    // A nearly symmetric object (a vase with a lug): ICP keeps the turn it started with, so the
    // turns about the near-axis are tried and the best fit kept.
    const FitQuality first = measureFit(fine, *dense, denseTree, best);
    const WeakestTurn weakest = weakestTurn(first.points, first.normals);
    if (weakest.turn && weakest.share < options.nearSymmetry && first.inlierShare > 0.5) {
        o3d::geometry::PointCloud sparse;
        for (std::size_t i = 0; i < fine.points_.size(); i += kSearchStride) {
            sparse.points_.push_back(fine.points_[i]);
            sparse.normals_.push_back(fine.normals_[i]);
        }
        const Eigen::Vector3d a = eigen(weakest.axis), c = eigen(weakest.axisPoint);
        Eigen::Matrix4d winner = best;
        double winnerScore = score(sparse, best);
        for (double turn = options.turnSearchDeg; turn < 359.9; turn += options.turnSearchDeg) {
            // Turned about its axis in the object frame, after the camera → object map.
            Eigen::Matrix4d spin = Eigen::Matrix4d::Identity();
            const Eigen::Matrix3d r = Eigen::AngleAxisd(turn * kPi / 180, a).toRotationMatrix();
            spin.block<3, 3>(0, 0) = r;
            spin.block<3, 1>(0, 3) = c - r * c;
            const Eigen::Matrix4d candidate = refine(sparse, spin * best, 10);
            const double candidateScore = score(sparse, candidate);
            if (candidateScore > winnerScore) {
                winnerScore = candidateScore;
                winner = candidate;
            }
        }
        best = refine(fine, winner, 40);
    }

    // The fit's quality, and what the scan leaves free.
    const FitQuality quality = measureFit(fine, *dense, denseTree, best);
    RegistrationResult result;
    result.scanPoints = scan->points_.size();
    result.inlierShare = quality.inlierShare;
    result.rmsMm = 1000 * quality.rms;
    if (quality.inlierShare < options.minInlierShare || !(result.rmsMm <= options.maxRmsMm)) {
        throw common::InputError("registration did not converge: " +
                                 std::to_string(static_cast<int>(100 * quality.inlierShare)) +
                                 "% of the scan lies within 1 mm of the mesh (at least " +
                                 std::to_string(static_cast<int>(100 * options.minInlierShare)) +
                                 "% wanted), residual " + std::to_string(result.rmsMm) +
                                 " mm — is it this object's mesh, in metres (--mesh-scale)?");
    }
    result.objectToCamera = poseOf(best.inverse());
    const FreeMotions free = freeMotions(quality.points, quality.normals, options.freeShare);
    if (free.count > 1) {
        throw common::InputError(
            "registration: the scan leaves " + std::to_string(free.count) +
            " motions of the mesh unmeasured (a sphere, a plane?): scan more of the "
            "object, or a part with features");
    }
    if (free.count == 1 && !free.turn) {
        throw common::InputError(
            "registration: the scan does not fix where the mesh slides (a "
            "cylinder or a flat side?): scan more of the object, its ends");
    }
    if (free.turn) {
        result.turnUnmeasured = true;
        result.axis = free.axis;
        result.axisPoint = free.axisPoint;
        result.objectToCamera = faceTowards(result.objectToCamera, result.axis, result.axisPoint,
                                            projector.center(), &result.turnSetDeg);
    }
    return result;
}

}  // namespace vpe::registration
