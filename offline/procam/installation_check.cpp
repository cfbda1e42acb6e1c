// SPDX-License-Identifier: MIT
// The bundle against the simulated installation's truth: pose, misregistration, visitor views.
#include "vpe/procam/installation_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vpe/common/input_error.h"
#include "vpe/common/quantile.h"
#include "vpe/image/image_metrics.h"
#include "vpe/registration/mesh_registration.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/procam/procam_simulator.h"

namespace vpe::procam {

namespace {

namespace sim = renderer::procam;
using registration::Pose;
using renderer::Vec3d;
using sim::ScreenObject;

constexpr double kPi = 3.14159265358979323846;
// The share of the true view's brightest object pixels that the exposure puts at 0.9.
constexpr double kExposureQuantile = 0.995;

Pose poseOf(const sim::RigidPose& pose) {
    return {pose.R, pose.t};
}

proto::Vec3d apply(const Pose& pose, const proto::Vec3d& p) {
    return {pose.R[0] * p.x + pose.R[1] * p.y + pose.R[2] * p.z + pose.t[0],
            pose.R[3] * p.x + pose.R[4] * p.y + pose.R[5] * p.z + pose.t[1],
            pose.R[6] * p.x + pose.R[7] * p.y + pose.R[8] * p.z + pose.t[2]};
}

}  // namespace

InstallationCheck checkInstallation(const sim::ProcamScene& scene,
                                    const proto::PinholeCamera& camera,
                                    const proto::BundleView& bundle,
                                    const InstallationCheckOptions& options) {
    if (!bundle.camera()) {
        throw common::InputError("the bundle carries no camera: bake it with --scan to check it");
    }
    if (!scene.object) {
        throw common::InputError("the installation has no object to check the bundle on");
    }
    const proto::PinholeCamera bundleProjector = proto::cameraOf(bundle.projector());
    const proto::PinholeCamera& trueProjectorRoom = scene.projector.camera;
    if (bundleProjector.width != trueProjectorRoom.width ||
        bundleProjector.height != trueProjectorRoom.height) {
        throw common::InputError("the bundle's projector is not the installation's size");
    }
    // The bundle's mesh must be the installation's object (a bundle baked with --scan and the
    // object's mesh): the truth's pose and texture are the object's.
    const proto::MeshView& bundleMesh = bundle.mesh();
    const ScreenObject& object = *scene.object;
    bool sameMesh = bundleMesh.vertexCount() == object.positions.size() &&
                    bundleMesh.indices.size() == object.indices.size();
    for (std::size_t v = 0; sameMesh && v < object.positions.size(); ++v) {
        sameMesh = std::abs(bundleMesh.positions[3 * v] - object.positions[v].x) < 1e-6f &&
                   std::abs(bundleMesh.positions[3 * v + 1] - object.positions[v].y) < 1e-6f &&
                   std::abs(bundleMesh.positions[3 * v + 2] - object.positions[v].z) < 1e-6f;
    }
    if (!sameMesh) {
        throw common::InputError(
            "the bundle's mesh is not the installation's object: --check compares "
            "bundles baked with the object's own mesh (vpe bake --scan DIR --mesh)");
    }
    InstallationCheck check;

    // Poses: the measured one (the bundle's camera), the true one (room → camera ∘ object →
    // room), and the true one turned by the rule when the mesh leaves a turn free.
    const Pose measured = registration::poseOfDevice(proto::cameraOf(*bundle.camera()));
    const Pose roomToCamera = registration::poseOfDevice(camera);
    Pose truth = registration::compose(roomToCamera, poseOf(scene.object->pose));
    const proto::MeshView& mesh = bundleMesh;
    std::vector<std::array<double, 3>> points, normals;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        points.push_back(
            {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
        normals.push_back({mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]});
    }
    const proto::PinholeCamera trueProjectorCamera =
        registration::inObjectFrame(trueProjectorRoom, registration::inverse(roomToCamera));
    const registration::FreeMotions free =
        registration::freeMotions(points, normals, registration::RegistrationOptions{}.freeShare);
    if (free.turn) {
        check.turnFree = true;
        truth = registration::faceTowards(truth, free.axis, free.axisPoint,
                                          trueProjectorCamera.center());
    }
    check.poseErrorDeg = registration::rotationDifferenceDeg(measured, truth);
    check.poseErrorMm = 1000 * registration::originDistanceM(measured, truth);
    const proto::PinholeCamera trueProjector =
        registration::inObjectFrame(trueProjectorCamera, truth);
    check.trueCamera = camera;
    check.trueCamera.R = truth.R;
    check.trueCamera.T = truth.t;

    // Misregistration: each vertex the bundle's projector lights goes to its projector pixel;
    // the true projector's ray through that pixel meets the true object somewhere: the distance.
    std::vector<renderer::Vec3f> positions(mesh.vertexCount()), vertexNormals(mesh.vertexCount());
    std::vector<renderer::Vec2f> uvs(mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        positions[v] = {mesh.positions[3 * v], mesh.positions[3 * v + 1],
                        mesh.positions[3 * v + 2]};
        vertexNormals[v] = {mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]};
    }
    const renderer::RenderMesh objectMesh{positions, vertexNormals, uvs, mesh.indices};
    const renderer::RayCaster caster(objectMesh);
    std::vector<double> distances;
    const proto::Vec3d bundleCentre = bundleProjector.center();
    const proto::Vec3d trueCentre = trueProjector.center();
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const proto::Vec3d x{points[v][0], points[v][1], points[v][2]};
        const proto::Vec3d n{normals[v][0], normals[v][1], normals[v][2]};
        const proto::Vec3d toProjector{bundleCentre.x - x.x, bundleCentre.y - x.y,
                                       bundleCentre.z - x.z};
        if (proto::dot(n, toProjector) <= 0) {
            continue;
        }
        const auto pixel = proto::projectToPixel(bundleProjector, x);
        if (!pixel || pixel->x < 0 || pixel->y < 0 || pixel->x > bundleProjector.width - 1 ||
            pixel->y > bundleProjector.height - 1) {
            continue;
        }
        const proto::Vec3d ray = proto::pixelRayDirection(bundleProjector, *pixel);
        const auto first = caster.closestHit(bundleCentre, ray);
        if (!first) {
            continue;
        }
        const proto::Vec3d lit{bundleCentre.x + first->t * ray.x, bundleCentre.y + first->t * ray.y,
                               bundleCentre.z + first->t * ray.z};
        if (std::hypot(lit.x - x.x, lit.y - x.y, lit.z - x.z) > 5e-4) {
            continue;  // the vertex is behind another part of the object
        }
        const proto::Vec3d trueRay = proto::pixelRayDirection(trueProjector, *pixel);
        const auto hit = caster.closestHit(trueCentre, trueRay);
        if (!hit) {
            continue;
        }
        const proto::Vec3d landed{trueCentre.x + hit->t * trueRay.x,
                                  trueCentre.y + hit->t * trueRay.y,
                                  trueCentre.z + hit->t * trueRay.z};
        distances.push_back(std::hypot(landed.x - x.x, landed.y - x.y, landed.z - x.z));
    }
    double squares = 0;
    for (const double d : distances) {
        squares += d * d;
    }
    check.misregistrationPoints = distances.size();
    if (!distances.empty()) {
        check.misregistrationRmsMm = 1000 * std::sqrt(squares / double(distances.size()));
        check.misregistrationP95Mm = 1000 * common::quantile(distances, 0.95);
        check.misregistrationMaxMm = 1000 * *std::max_element(distances.begin(), distances.end());
    }

    // What a visitor sees: the frames the bundle renders, with its own projector and with the
    // true one, each shown by the true projector on the true object (the simulator, without
    // noise), seen from the bundle's viewer.
    const renderer::BundleScene bundleScene(bundle, options.preset);
    const proto::Vec3d viewer = bundleScene.bundleViewer();
    const Pose objectToRoom = registration::compose(registration::inverse(roomToCamera), truth);
    float low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const renderer::Vec3f& p : positions) {
        low[0] = std::min(low[0], p.x), high[0] = std::max(high[0], p.x);
        low[1] = std::min(low[1], p.y), high[1] = std::max(high[1], p.y);
        low[2] = std::min(low[2], p.z), high[2] = std::max(high[2], p.z);
    }
    const proto::Vec3d middle{0.5 * double(low[0] + high[0]), 0.5 * double(low[1] + high[1]),
                              0.5 * double(low[2] + high[2])};
    sim::SimulatedCamera visitor;
    visitor.camera =
        proto::cameraLookingAt(options.viewWidth, options.viewHeight, options.viewFovDeg,
                               apply(objectToRoom, viewer), apply(objectToRoom, middle));
    visitor.fullWellElectrons = 0;
    visitor.readNoiseElectrons = 0;
    visitor.bits = 10;
    visitor.monochrome = false;
    const sim::ProcamSimulator simulator(scene, visitor, options.threads);
    const sim::CameraTruth seen = simulator.cameraTruth();

    std::vector<proto::Vec3d> lights = options.lights;
    if (lights.empty()) {
        for (const double degrees : {0.0, 90.0, 180.0, 270.0}) {
            const double a = degrees * kPi / 180;
            lights.push_back({0.5 * std::sin(a), 0.3, 0.2 + 0.5 * std::cos(a)});
        }
    }
    renderer::RenderOptions render;
    render.threads = options.threads;
    for (const proto::Vec3d& light : lights) {
        renderer::VirtualLight virtualLight;
        virtualLight.position = light;
        renderer::RenderScene measuredScene = bundleScene.scene(virtualLight, viewer);
        renderer::RenderScene trueScene = measuredScene;
        trueScene.projector.camera = trueProjector;
        render.gain = 1;
        render.gain = std::max(1e-3, renderer::gainForClippedFraction(
                                         renderer::renderProjectorFrame(trueScene, render), 0.005));
        const renderer::RgbImage measuredView =
            simulator.radiance(renderer::renderProjectorFrame(measuredScene, render).level);
        const renderer::RgbImage trueView =
            simulator.radiance(renderer::renderProjectorFrame(trueScene, render).level);
        // One exposure for both, from the true view's object pixels; 8-bit sRGB, as people see
        // it (image_metrics.h).
        std::vector<double> luminance;
        std::vector<std::uint8_t> mask(trueView.pixelCount(), 0);
        for (std::size_t p = 0; p < trueView.pixelCount(); ++p) {
            if (!std::isnan(seen.pointCamera[3 * p])) {
                const float* rgb = &trueView.values[3 * p];
                luminance.push_back(sim::luminance709(rgb[0], rgb[1], rgb[2]));
                mask[p] = 1;
            }
        }
        const double exposure =
            0.9 / std::max(1e-12, common::quantile(luminance, kExposureQuantile));
        VisitorComparison comparison;
        comparison.light = light;
        comparison.measured =
            image::toSrgb8(measuredView.values, measuredView.width, measuredView.height, exposure);
        comparison.truth =
            image::toSrgb8(trueView.values, trueView.width, trueView.height, exposure);
        comparison.psnr = image::psnr(comparison.measured, comparison.truth, mask);
        check.views.push_back(std::move(comparison));
    }
    check.psnrMin = std::numeric_limits<double>::infinity();
    for (const VisitorComparison& view : check.views) {
        check.psnrMean += view.psnr / double(check.views.size());
        check.psnrMin = std::min(check.psnrMin, view.psnr);
    }
    return check;
}

}  // namespace vpe::procam
