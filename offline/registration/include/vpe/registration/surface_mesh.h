// SPDX-License-Identifier: MIT
// The scan's own surface as the screen object, for an installation without a mesh: the
// measured projector pixels joined into triangles, in an object frame of its own, with a uv
// parameterization chosen for the shape — cylindrical about the axis of revolution when the
// surface is one (a turned vase: the seam at the back, texels square where its radius is the
// mean), else the projector's own image (every lit point has one projector pixel, so the chart
// never folds; texels stretch only where the projector grazes).
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/registration/mesh_registration.h"
#include "vpe/scan/projector_surface.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::registration {

enum class SurfaceChart { kCylindrical, kProjector };

struct SurfaceMeshOptions {
    int step = 0;  // projector pixels between vertices; 0: about 160 along the object's width
    // Triangles with an edge longer than this many grid steps' worth of surface (at their depth)
    // span a jump and are left out.
    double maxEdgeSteps = 4;
    // The normals must meet a common axis to this RMS (metres) for a cylindrical chart.
    double maxAxisResidual = 0.0015;
};

struct AxisFit {
    bool valid = false;
    std::array<double, 3> direction{}, point{};  // camera frame; point nearest the origin
    double rmsM = 0;                             // RMS distance of the normal lines from the axis
    double pitch = 0;  // a helix's pitch (metres per radian); ~0 for a surface of revolution
};

// Pottmann and Randrup ("Rotational and helical surface approximation for reverse
// engineering", 1998): the normal lines of a surface of revolution all meet its axis, so the
// axis is the linear line complex that fits the normals' Plücker coordinates best.
AxisFit fitRevolutionAxis(const scan::ProjectorSurface& surface);

struct SurfaceMesh {
    scene::ScreenMesh mesh;  // object frame
    Pose objectToCamera;
    SurfaceChart chart = SurfaceChart::kProjector;
    AxisFit axis;
    int step = 0;
};

// Throws InputError when the scan measured too little to make a surface.
SurfaceMesh makeSurfaceMesh(const scan::ProjectorSurface& surface,
                            const proto::PinholeCamera& projectorInCameraFrame,
                            const SurfaceMeshOptions& options = {});

const char* surfaceChartName(SurfaceChart chart);

// In a scan folder: surface-mesh.obj (object frame) and surface-frame.json (the object frame in
// the camera's: R, t; the chart; the axis fit).
inline constexpr const char* kSurfaceMeshFile = "surface-mesh.obj";
inline constexpr const char* kSurfaceFrameFile = "surface-frame.json";
void writeSurfaceMesh(const SurfaceMesh& surface, const std::filesystem::path& folder);
// Reads both back (InputError naming the file).
SurfaceMesh readSurfaceMesh(const std::filesystem::path& folder);

}  // namespace vpe::registration
