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
    // The smallest eigenvalue of the point-to-plane information matrix, relative to the largest
    // (rotations scaled by the object's radius), below which a motion is not measured.
    double degeneracy = 2e-4;
    std::uint64_t seed = 1;
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
// matrix of its points and normals (rotations about their centroid scaled by their RMS radius),
// the eigenvectors whose eigenvalue is below `degeneracy` times the largest. One such motion
// that is a turn about an axis (no slide along it) is a surface of revolution's free turn.
struct FreeMotions {
    int count = 0;
    bool turn = false;  // count == 1 and it is a turn
    std::array<double, 3> axis{}, axisPoint{};
};
FreeMotions freeMotions(const std::vector<std::array<double, 3>>& points,
                        const std::vector<std::array<double, 3>>& normals, double degeneracy);

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

// The rotation angle between two poses (degrees) and the distance between where they put the
// object's origin (metres).
double rotationDifferenceDeg(const Pose& a, const Pose& b);
double originDistanceM(const Pose& a, const Pose& b);

}  // namespace vpe::registration
