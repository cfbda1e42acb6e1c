// SPDX-License-Identifier: MIT
// ProcamSimulator: the camera's samples traced once, then per image the projector's light
// (response, black level, defocus), a weighted sum per camera pixel, one bounce of
// interreflection, and the sensor.
#include "vpe/renderer/procam/procam_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "vpe/renderer/cpu/parallel_rows.h"
#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/surface_point.h"

#include "interreflection.h"
#include "projector_light.h"
#include "sensor_noise.h"
#include "vector_math.h"

namespace vpe::renderer::procam {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Occluders closer to the end of a shadow ray than this fraction of its length do not count:
// far above the rounding of the end point, far below any real occluder (as visitor_view.cpp).
constexpr double kShadowTolerance = 1e-6;

}  // namespace

// One camera sample: where its point lies in the projector image and the weight of the light
// there (ρ/π · S / samples, per channel); px is NaN when the projector does not reach it.
struct CameraSample {
    float px, py;
    float weight[3];
};

struct ProcamSimulator::Impl {
    ProcamScene scene;
    SimulatedCamera camera;
    int threads = 0;

    // The object (room frame) and the board, as one mesh: triangles [0, objectTriangles) are
    // the object's.
    std::vector<Vec3f> positions, normals;
    std::vector<Vec2f> uvs;
    std::vector<std::uint32_t> indices;
    std::uint32_t objectTriangles = 0;
    std::array<double, 2> objectHeights{0, 0};  // object frame y range, for the albedo
    std::unique_ptr<RayCaster> caster;
    Vec3d projectorCentre, cameraCentre;

    int samplesPerPixel = 1;
    std::vector<CameraSample> samples;  // pixels × samplesPerPixel
    std::vector<float> ambient;         // pixels × 3: the room's light, reflected
    // Interreflection: the mean ρ/π of a pixel's object samples (pixels × 3) and the texture
    // coordinate where its bounce light is looked up (pixels × 2).
    std::vector<float> bounceAlbedo, bounceUv;
    std::unique_ptr<Interreflection> interreflection;

    RenderMesh mesh() const { return {positions, normals, uvs, indices}; }
    bool isObject(std::uint32_t triangle) const { return triangle < objectTriangles; }

    void buildMesh();
    std::array<double, 3> albedoAt(const SurfacePoint& point) const;
    // S at X with normal n facing the ray's side: P·cos θp / d², 0 when the projector is
    // behind the surface or shadowed, and the projector pixel (nothing outside its image).
    bool projectorReaches(const Vec3d& point, const Vec3d& normal, double& scale,
                          Vec2d& pixel) const;
    void traceSamples();
};

void ProcamSimulator::Impl::buildMesh() {
    if (scene.object) {
        const ScreenObject& o = *scene.object;
        double low = std::numeric_limits<double>::infinity(), high = -low;
        for (std::size_t i = 0; i < o.positions.size(); ++i) {
            const Vec3d p = toDouble(o.positions[i]);
            low = std::min(low, p.y);
            high = std::max(high, p.y);
            const Vec3d room = o.pose.apply(p);
            const Vec3d n = o.pose.rotate(toDouble(o.normals[i]));
            positions.push_back({float(room.x), float(room.y), float(room.z)});
            normals.push_back({float(n.x), float(n.y), float(n.z)});
        }
        objectHeights = {low, high};
        uvs = o.uvs;
        indices = o.indices;
        objectTriangles = static_cast<std::uint32_t>(o.indices.size() / 3);
    }
    if (scene.board) {
        const CheckerBoard& b = *scene.board;
        const double x0 = -b.squareM - b.marginM, y0 = x0;
        const double x1 = (b.squaresX - 1) * b.squareM + b.marginM;
        const double y1 = (b.squaresY - 1) * b.squareM + b.marginM;
        const auto base = static_cast<std::uint32_t>(positions.size());
        const Vec3d n = b.pose.rotate({0, 0, -1});  // the printed face
        for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) {
            const Vec3d p = b.pose.apply({x, y, 0});
            positions.push_back({float(p.x), float(p.y), float(p.z)});
            normals.push_back({float(n.x), float(n.y), float(n.z)});
            uvs.push_back({0, 0});
        }
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    caster = std::make_unique<RayCaster>(mesh());
}

std::array<double, 3> ProcamSimulator::Impl::albedoAt(const SurfacePoint& point) const {
    if (isObject(point.triangle)) {
        const Vec3d local = scene.object->pose.inverse().apply(point.position);
        return plasterAlbedoAt(scene.albedo, local, objectHeights);
    }
    const CheckerBoard& b = *scene.board;
    const Vec3d q = b.pose.inverse().apply(point.position);
    const int column = static_cast<int>(std::floor(q.x / b.squareM)) + 1;
    const int row = static_cast<int>(std::floor(q.y / b.squareM)) + 1;
    const bool inSquares = column >= 0 && column < b.squaresX && row >= 0 && row < b.squaresY;
    return inSquares && (column + row) % 2 == 0 ? b.dark : b.light;
}

bool ProcamSimulator::Impl::projectorReaches(const Vec3d& point, const Vec3d& normal, double& scale,
                                             Vec2d& pixel) const {
    const Vec3d toProjector = projectorCentre - point;
    const double distanceSquared = proto::dot(toProjector, toProjector);
    const double cosine = proto::dot(normal, toProjector) / std::sqrt(distanceSquared);
    if (!(cosine > 0)) {
        return false;
    }
    const proto::PinholeCamera& projector = scene.projector.camera;
    const auto projected = proto::projectToPixel(projector, point);
    if (!projected || projected->x < -0.5 || projected->x > projector.width - 0.5 ||
        projected->y < -0.5 || projected->y > projector.height - 0.5) {
        return false;
    }
    if (caster->anyHit(projectorCentre, point - projectorCentre, 0.0, 1.0 - kShadowTolerance)) {
        return false;
    }
    scale = scene.projector.peakIrradiance * cosine / distanceSquared;
    pixel = *projected;
    return true;
}

void ProcamSimulator::Impl::traceSamples() {
    const proto::PinholeCamera& c = camera.camera;
    const int n = camera.samples;
    samplesPerPixel = n * n;
    const std::size_t pixels =
        static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
    samples.assign(pixels * static_cast<std::size_t>(samplesPerPixel), {kNaN, kNaN, {0, 0, 0}});
    ambient.assign(pixels * 3, 0.0f);
    const bool bounce = interreflection != nullptr;
    if (bounce) {
        bounceAlbedo.assign(pixels * 3, 0.0f);
        bounceUv.assign(pixels * 2, kNaN);
    }
    const double share = 1.0 / samplesPerPixel;
    const RenderMesh view = mesh();
    forEachRow(c.height, threads, [&](int y) {
        for (int x = 0; x < c.width; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(y) * c.width + x;
            for (int b = 0; b < n; ++b) {
                for (int a = 0; a < n; ++a) {
                    const Vec2d position{x + (a + 0.5) / n - 0.5, y + (b + 0.5) / n - 0.5};
                    const Vec3d direction = proto::pixelRayDirection(c, position);
                    const auto hit = caster->closestHit(cameraCentre, direction);
                    if (!hit) {
                        continue;
                    }
                    const SurfacePoint point = surfacePoint(view, cameraCentre, direction, *hit);
                    const std::array<double, 3> albedo = albedoAt(point);
                    for (std::size_t ch = 0; ch < 3; ++ch) {
                        ambient[3 * pixel + ch] +=
                            float(albedo[ch] / kPi * scene.room.ambient[ch] * share);
                    }
                    if (bounce && isObject(hit->triangle)) {
                        for (std::size_t ch = 0; ch < 3; ++ch) {
                            bounceAlbedo[3 * pixel + ch] += float(albedo[ch] / kPi * share);
                        }
                        if (std::isnan(bounceUv[2 * pixel])) {
                            bounceUv[2 * pixel] = float(point.uv.x);
                            bounceUv[2 * pixel + 1] = float(point.uv.y);
                        }
                    }
                    double scale = 0;
                    Vec2d projected;
                    if (!projectorReaches(point.position, point.normal, scale, projected)) {
                        continue;
                    }
                    CameraSample& sample =
                        samples[pixel * static_cast<std::size_t>(samplesPerPixel) +
                                static_cast<std::size_t>(b * n + a)];
                    sample.px = float(projected.x);
                    sample.py = float(projected.y);
                    for (std::size_t ch = 0; ch < 3; ++ch) {
                        sample.weight[ch] = float(albedo[ch] / kPi * scale * share);
                    }
                }
            }
        }
    });
}

ProcamSimulator::ProcamSimulator(const ProcamScene& scene, const SimulatedCamera& camera,
                                 int threads)
    : impl_(std::make_unique<Impl>()) {
    if (auto problem = checkProcamScene(scene); !problem.empty()) {
        throw std::invalid_argument("procam simulator: " + problem);
    }
    if (auto problem = checkSimulatedCamera(camera); !problem.empty()) {
        throw std::invalid_argument("procam simulator: " + problem);
    }
    Impl& s = *impl_;
    s.scene = scene;
    s.camera = camera;
    s.threads = threads;
    s.projectorCentre = scene.projector.camera.center();
    s.cameraCentre = camera.camera.center();
    s.buildMesh();
    if (scene.object && scene.room.interreflection) {
        s.interreflection = std::make_unique<Interreflection>(
            s.mesh(), s.objectTriangles, scene.room.interreflectionGrid,
            [&s](const SurfacePoint& point) { return s.albedoAt(point); },
            [&s](const Vec3d& point, const Vec3d& normal, double& scale, Vec2d& pixel) {
                return s.projectorReaches(point, normal, scale, pixel);
            },
            *s.caster, threads);
    }
    s.traceSamples();
}

ProcamSimulator::~ProcamSimulator() = default;

const ProcamScene& ProcamSimulator::scene() const {
    return impl_->scene;
}

const SimulatedCamera& ProcamSimulator::camera() const {
    return impl_->camera;
}

RgbImage ProcamSimulator::radiance(const RgbImage& levels) const {
    return radianceAt(levels, std::nullopt);
}

RgbImage ProcamSimulator::radiance(const RgbImage& levels, std::uint64_t frame) const {
    const Impl& s = *impl_;
    if (!s.scene.projector.dlp.enabled()) {
        return radianceAt(levels, std::nullopt);
    }
    return radianceAt(levels, dlpWindowStart(s.camera.seed, frame));
}

RgbImage ProcamSimulator::radianceAt(const RgbImage& levels,
                                     std::optional<double> windowStart) const {
    const Impl& s = *impl_;
    const ProjectorLight light(s.scene.projector, levels, windowStart);
    std::vector<float> bounce;
    if (s.interreflection) {
        bounce = s.interreflection->bounce(light, s.scene.room.ambient);
    }
    const proto::PinholeCamera& c = s.camera.camera;
    RgbImage out(c.width, c.height);
    const auto perPixel = static_cast<std::size_t>(s.samplesPerPixel);
    forEachRow(c.height, s.threads, [&](int y) {
        for (int x = 0; x < c.width; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(y) * c.width + x;
            float sum[3] = {s.ambient[3 * pixel], s.ambient[3 * pixel + 1],
                            s.ambient[3 * pixel + 2]};
            for (std::size_t k = 0; k < perPixel; ++k) {
                const CameraSample& sample = s.samples[pixel * perPixel + k];
                if (std::isnan(sample.px)) {
                    continue;
                }
                const std::array<float, 3> rgb = light.at(sample.px, sample.py);
                for (std::size_t ch = 0; ch < 3; ++ch) {
                    sum[ch] += sample.weight[ch] * rgb[ch];
                }
            }
            if (!bounce.empty() && !std::isnan(s.bounceUv[2 * pixel])) {
                const std::array<float, 3> e = s.interreflection->lookup(
                    bounce, s.bounceUv[2 * pixel], s.bounceUv[2 * pixel + 1]);
                for (std::size_t ch = 0; ch < 3; ++ch) {
                    sum[ch] += s.bounceAlbedo[3 * pixel + ch] * e[ch];
                }
            }
            float* o = out.pixel(x, y);
            o[0] = sum[0];
            o[1] = sum[1];
            o[2] = sum[2];
        }
    });
    return out;
}

RgbImage ProcamSimulator::radiance(std::span<const std::uint8_t> codes) const {
    return radiance(levelsOf(impl_->scene.projector.camera, codes));
}

RgbImage ProcamSimulator::radiance(std::span<const std::uint8_t> codes, std::uint64_t frame) const {
    return radiance(levelsOf(impl_->scene.projector.camera, codes), frame);
}

RgbImage ProcamSimulator::levelsOf(const proto::PinholeCamera& p,
                                   std::span<const std::uint8_t> codes) {
    if (codes.size() != static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height)) {
        throw std::invalid_argument("procam simulator: the pattern has " +
                                    std::to_string(codes.size()) + " pixels, the projector " +
                                    std::to_string(p.width) + "x" + std::to_string(p.height));
    }
    RgbImage levels(p.width, p.height);
    for (std::size_t i = 0; i < codes.size(); ++i) {
        const float level = static_cast<float>(codes[i]) / 255.0f;
        levels.values[3 * i] = levels.values[3 * i + 1] = levels.values[3 * i + 2] = level;
    }
    return levels;
}

CameraFrame ProcamSimulator::expose(const RgbImage& radiance, std::uint64_t frame) const {
    return exposeSensor(impl_->camera, radiance, frame, impl_->threads);
}

CameraFrame ProcamSimulator::expose(const RgbImage& radiance, std::uint64_t frame,
                                    const SimulatedCamera& sensor) const {
    if (auto problem = checkSimulatedCamera(sensor); !problem.empty()) {
        throw std::invalid_argument("procam simulator: " + problem);
    }
    return exposeSensor(sensor, radiance, frame, impl_->threads);
}

CameraTruth ProcamSimulator::cameraTruth() const {
    const Impl& s = *impl_;
    const proto::PinholeCamera& c = s.camera.camera;
    const std::size_t pixels =
        static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
    CameraTruth truth;
    truth.projectorX.assign(pixels, kNaN);
    truth.projectorY.assign(pixels, kNaN);
    truth.centreX.assign(pixels, kNaN);
    truth.centreY.assign(pixels, kNaN);
    truth.pointCamera.assign(pixels * 3, kNaN);
    const RenderMesh view = s.mesh();
    forEachRow(c.height, s.threads, [&](int y) {
        for (int x = 0; x < c.width; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(y) * c.width + x;
            const Vec3d direction = proto::pixelRayDirection(c, {double(x), double(y)});
            if (const auto hit = s.caster->closestHit(s.cameraCentre, direction)) {
                const SurfacePoint point = surfacePoint(view, s.cameraCentre, direction, *hit);
                const Vec3d local = c.toCamera(point.position);
                truth.pointCamera[3 * pixel] = float(local.x);
                truth.pointCamera[3 * pixel + 1] = float(local.y);
                truth.pointCamera[3 * pixel + 2] = float(local.z);
                double scale = 0;
                Vec2d projected;
                if (s.projectorReaches(point.position, point.normal, scale, projected)) {
                    truth.centreX[pixel] = float(projected.x);
                    truth.centreY[pixel] = float(projected.y);
                }
            }
            // The pixel's own samples, as radiance() sums them.
            double sumX = 0, sumY = 0, weights = 0;
            const auto perPixel = static_cast<std::size_t>(s.samplesPerPixel);
            for (std::size_t k = 0; k < perPixel; ++k) {
                const CameraSample& sample = s.samples[pixel * perPixel + k];
                if (std::isnan(sample.px)) {
                    continue;
                }
                const double weight =
                    luminance709(sample.weight[0], sample.weight[1], sample.weight[2]);
                sumX += weight * double(sample.px);
                sumY += weight * double(sample.py);
                weights += weight;
            }
            if (weights > 0) {
                truth.projectorX[pixel] = float(sumX / weights);
                truth.projectorY[pixel] = float(sumY / weights);
            }
        }
    });
    return truth;
}

ProjectorTruth ProcamSimulator::projectorTruth() const {
    const Impl& s = *impl_;
    const proto::PinholeCamera& p = s.scene.projector.camera;
    const proto::PinholeCamera& c = s.camera.camera;
    ProjectorTruth truth;
    truth.width = p.width;
    truth.height = p.height;
    const std::size_t pixels =
        static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height);
    truth.position.assign(pixels * 3, kNaN);
    truth.normal.assign(pixels * 3, kNaN);
    truth.seen.assign(pixels, 0);
    const RenderMesh view = s.mesh();
    forEachRow(p.height, s.threads, [&](int y) {
        for (int x = 0; x < p.width; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(y) * p.width + x;
            const Vec3d direction = proto::pixelRayDirection(p, {double(x), double(y)});
            const auto hit = s.caster->closestHit(s.projectorCentre, direction);
            if (!hit) {
                continue;
            }
            const SurfacePoint point = surfacePoint(view, s.projectorCentre, direction, *hit);
            const Vec3d position = c.toCamera(point.position);
            const Vec3d normal = c.toCamera(point.position + point.normal) - position;
            const float values[6] = {float(position.x), float(position.y), float(position.z),
                                     float(normal.x),   float(normal.y),   float(normal.z)};
            std::copy(values, values + 3, truth.position.begin() + std::ptrdiff_t(3 * pixel));
            std::copy(values + 3, values + 6, truth.normal.begin() + std::ptrdiff_t(3 * pixel));
            const auto seenAt = proto::projectToPixel(c, point.position);
            const Vec3d toCamera = s.cameraCentre - point.position;
            truth.seen[pixel] = seenAt && seenAt->x >= -0.5 && seenAt->x <= c.width - 0.5 &&
                                seenAt->y >= -0.5 && seenAt->y <= c.height - 0.5 &&
                                proto::dot(point.normal, toCamera) > 0 &&
                                !s.caster->anyHit(s.cameraCentre, point.position - s.cameraCentre,
                                                  0.0, 1.0 - kShadowTolerance);
        }
    });
    return truth;
}

}  // namespace vpe::renderer::procam
