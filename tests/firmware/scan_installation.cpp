// SPDX-License-Identifier: MIT
// The scan tests' installation.
#include "scan_installation.h"

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/procam/scene_file.h"

namespace vpe::firmware::testing {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

std::string ballAndWallObj(double radius, double wallDistance) {
    std::ostringstream obj;
    obj.precision(9);
    constexpr int kRings = 16, kSegments = 32;
    // Sphere vertices ring by ring (pole to pole), each ring closing on a repeated seam vertex.
    for (int r = 0; r <= kRings; ++r) {
        const double theta = kPi * r / kRings;
        for (int s = 0; s <= kSegments; ++s) {
            const double phi = 2 * kPi * s / kSegments;
            const double nx = std::sin(theta) * std::cos(phi), ny = std::cos(theta),
                         nz = std::sin(theta) * std::sin(phi);
            obj << "v " << radius * nx << " " << radius + radius * ny << " " << radius * nz << "\n";
            obj << "vn " << nx << " " << ny << " " << nz << "\n";
            obj << "vt " << static_cast<double>(s) / kSegments << " "
                << 1.0 - static_cast<double>(r) / kRings << "\n";
        }
    }
    const auto index = [](int r, int s) { return r * (kSegments + 1) + s + 1; };
    const auto face = [&obj](int a, int b, int c) {
        obj << "f " << a << "/" << a << "/" << a << " " << b << "/" << b << "/" << b << " " << c
            << "/" << c << "/" << c << "\n";
    };
    for (int r = 0; r < kRings; ++r) {
        for (int s = 0; s < kSegments; ++s) {
            // Counter-clockwise seen from outside.
            const int a = index(r, s), b = index(r + 1, s), c = index(r + 1, s + 1),
                      d = index(r, s + 1);
            if (r > 0) {
                face(a, d, b);
            }
            if (r < kRings - 1) {
                face(d, c, b);
            }
        }
    }
    // The wall: 0.8 × 0.6 m facing +z, its foot below the ball's.
    const int first = (kRings + 1) * (kSegments + 1) + 1;
    const double x0 = -0.4, x1 = 0.4, y0 = -0.2, y1 = 0.4, z = -wallDistance;
    for (const auto& [x, y, u, v] :
         {std::array<double, 4>{x0, y0, 0, 0}, {x1, y0, 1, 0}, {x1, y1, 1, 1}, {x0, y1, 0, 1}}) {
        obj << "v " << x << " " << y << " " << z << "\nvn 0 0 1\nvt " << u << " " << v << "\n";
    }
    face(first, first + 1, first + 2);
    face(first, first + 2, first + 3);
    return obj.str();
}

ScanInstallation writeScanInstallation(const std::filesystem::path& folder, int bits,
                                       renderer::procam::CameraResponse response) {
    const double radius = 0.07;
    std::ofstream(folder / "ball-wall.obj") << ballAndWallObj(radius, 0.12);
    ScanInstallation installation;
    installation.sceneFile = folder / "installation.toml";
    renderer::procam::ProcamScene& scene = installation.scene;
    scene.object = renderer::procam::readObjectMesh(folder / "ball-wall.obj");
    const proto::Vec3d target{0, radius, 0};
    scene.projector.camera = proto::cameraLookingAt(320, 180, 32.0, {0.04, 0.12, 0.6}, target);
    scene.projector.blurPixels = 0.6;
    scene.room.ambient = {0.01, 0.01, 0.01};
    scene.room.interreflection = false;  // a ball before a wall: little, and slow to trace
    renderer::procam::SimulatedCamera& camera = installation.camera;
    camera.camera = proto::cameraLookingAt(320, 240, 40.0, {-0.16, 0.16, 0.52}, target);
    camera.exposure = 0.9;
    camera.bits = bits;
    camera.response = response;
    camera.samples = 2;
    camera.monochrome = true;
    camera.seed = 7;
    renderer::procam::writeSceneFile(installation.sceneFile, scene, camera, "ball-wall.obj");
    return installation;
}

}  // namespace vpe::firmware::testing
