// SPDX-License-Identifier: MIT
// registerMesh: where the screen object's mesh stands in the scan — a global alignment (FPFH
// features matched by RANSAC, tried from several seeds) refined by point-to-plane ICP, all
// Open3D's — and what the scan cannot tell: a turned vase looks the same at any turn about
// its axis, so that turn is set by a rule (the mesh's front, +z, towards the projector) and
// reported, not guessed (docs/install.md, "Registration").
#pragma once

#include <array>
#include <cstdint>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/scan/projector_surface.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::registration {

// X_camera = R·X_object + t (metres, R row-major).
struct Pose {
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::array<double, 3> t{};
};

struct RegistrationOptions {
    double voxelM = 0.002;  // the global alignment's point spacing
    int globalTrials = 4;   // RANSAC runs, each from its own seed: the best ICP wins
    int ransacIterations = 30000;
    double maxRmsMm = 0.5;         // refused above: the mesh is not this object, or not its scale
    double minInlierShare = 0.85;  // of the scan's points within 1 mm of the mesh after ICP
    // A motion whose information is below this share of the strongest is not measured
    // (freeMotions): a turned vase's is below 1e-5 (its facets), a lug of half a percent of the
    // surface lifts it to 1e-3.
    double freeShare = 1e-4;
    // Nearly a surface of revolution (the smallest eigenvalue of the information matrix below
    // this share of the largest: a lug, a spout): the turn about that axis is searched in steps
    // of turnSearchDeg from the best fit, each refined, since ICP alone keeps the turn it started
    // with.
    double nearSymmetry = 0.02;
    double turnSearchDeg = 30;
    std::uint64_t seed = 1;
    unsigned threads = 0;  // the fine fit's nearest-neighbour searches; 0: all cores
};

struct RegistrationResult {
    Pose objectToCamera;
    double rmsMm = 0;        // point-to-plane, over the inliers
    double inlierShare = 0;  // of the scan's points
    std::size_t scanPoints = 0;
    // The object turns about an axis without the scan noticing (a surface of revolution): the
    // axis in the object frame (unit, through axisPoint), and the turn set by the rule.
    bool turnUnmeasured = false;
    std::array<double, 3> axis{}, axisPoint{};
    double turnSetDeg = 0;
};

// The motions of a surface that move it along itself: from the point-to-plane information
// matrix of its points and normals (rotations about their centroid scaled by their RMS radius,
// so that every motion is in metres at the surface), the eigenvectors whose eigenvalue is below
// maxShare of the largest. One such motion that is a turn about an axis (no slide along it) is a
// surface of revolution's free turn.
struct FreeMotions {
    int count = 0;
    bool turn = false;  // count == 1 and it is a turn
    std::array<double, 3> axis{}, axisPoint{};
};
FreeMotions freeMotions(const std::vector<std::array<double, 3>>& points,
                        const std::vector<std::array<double, 3>>& normals, double maxShare = 1e-4);

// The motion a surface is least sure of — the eigenvector of the smallest eigenvalue — when it
// is a turn about an axis, with that eigenvalue's share of the largest (object frame).
struct WeakestTurn {
    bool turn = false;
    double share = 1;
    std::array<double, 3> axis{}, axisPoint{};
};
WeakestTurn weakestTurn(const std::vector<std::array<double, 3>>& points,
                        const std::vector<std::array<double, 3>>& normals);

// Throws InputError for a registration that does not converge (too few inliers, too large a
// residual) or a pose the scan leaves undetermined other than by a turn about an axis (a
// cylinder slid along itself, a plane).
RegistrationResult registerMesh(const scene::ScreenMesh& mesh, const scan::ProjectorSurface& scan,
                                const proto::PinholeCamera& projectorInCameraFrame,
                                const RegistrationOptions& options = {});

// For a pose whose turn about `axis` (object frame, through axisPoint) is free: the pose turned
// about it so that the object's +z, perpendicular to the axis, points at `target` (camera frame).
// Returns the turn applied in degrees through `turnDeg`.
Pose faceTowards(const Pose& pose, const std::array<double, 3>& axis,
                 const std::array<double, 3>& axisPoint, const proto::Vec3d& target,
                 double* turnDeg = nullptr);

// A device seen from the camera's frame (X_device = R·X_camera + T), re-expressed for the
// object's frame through objectToCamera: X_device = R·(R_o·X + t_o) + T.
proto::PinholeCamera inObjectFrame(const proto::PinholeCamera& device, const Pose& objectToCamera);

// The pose of a device (X_device = R·X + T) as a Pose, and back into a device's R, T.
Pose poseOfDevice(const proto::PinholeCamera& device);

// (outer ∘ inner)(X) = outer(inner(X)), and the inverse.
Pose compose(const Pose& outer, const Pose& inner);
Pose inverse(const Pose& pose);

// The rotation angle between two poses (degrees) and the distance between where they put the
// object's origin (metres).
double rotationDifferenceDeg(const Pose& a, const Pose& b);
double originDistanceM(const Pose& a, const Pose& b);

}  // namespace vpe::registration
