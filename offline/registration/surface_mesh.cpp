// SPDX-License-Identifier: MIT
// The scan's surface as a mesh: the axis fit, the object frame, the grid triangles, the uvs.
#include "vpe/registration/surface_mesh.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"

namespace vpe::registration {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kAxisSamples = 50000;
constexpr int kTargetVertices = 160;  // along the object's width in the projector's image
// A helix whose pitch exceeds this (metres per radian) is not a surface of revolution.
constexpr double kMaxPitch = 0.002;

struct Sample {
    Eigen::Vector3d position, normal;
};

std::vector<Sample> measured(const scan::ProjectorSurface& s, std::size_t limit) {
    std::vector<Sample> all;
    const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (!std::isnan(s.position[3 * p]) && !std::isnan(s.normal[3 * p])) {
            all.push_back({{s.position[3 * p], s.position[3 * p + 1], s.position[3 * p + 2]},
                           {s.normal[3 * p], s.normal[3 * p + 1], s.normal[3 * p + 2]}});
        }
    }
    if (all.size() <= limit) {
        return all;
    }
    std::vector<Sample> thinned;
    const std::size_t stride = all.size() / limit + 1;
    for (std::size_t i = 0; i < all.size(); i += stride) {
        thinned.push_back(all[i]);
    }
    return thinned;
}

}  // namespace

const char* surfaceChartName(SurfaceChart chart) {
    return chart == SurfaceChart::kCylindrical ? "cylindrical" : "projector";
}

AxisFit fitRevolutionAxis(const scan::ProjectorSurface& surface) {
    const std::vector<Sample> samples = measured(surface, kAxisSamples);
    AxisFit fit;
    if (samples.size() < 100) {
        return fit;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Sample& s : samples) {
        centroid += s.position;
    }
    centroid /= double(samples.size());
    // Σ v vᵀ for v = (p × n, n), p relative to the centroid: minimise cᵀ·Schur·c with |c| = 1.
    Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
    for (const Sample& s : samples) {
        Eigen::Matrix<double, 6, 1> v;
        v.head<3>() = (s.position - centroid).cross(s.normal);
        v.tail<3>() = s.normal;
        M += v * v.transpose();
    }
    const Eigen::Matrix3d A = M.topLeftCorner<3, 3>(), B = M.topRightCorner<3, 3>(),
                          C = M.bottomRightCorner<3, 3>();
    if (std::abs(C.determinant()) < 1e-18) {
        return fit;  // the normals do not span space (a plane)
    }
    const Eigen::Matrix3d schur = A - B * C.inverse() * B.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(schur);
    const Eigen::Vector3d c = solver.eigenvectors().col(0);
    const Eigen::Vector3d cbar = -C.inverse() * B.transpose() * c;
    const Eigen::Vector3d axis = c.normalized();
    fit.pitch = c.dot(cbar) / c.squaredNorm();
    // The axis' point nearest the centroid (pure rotation part of the complex), back in the
    // camera's frame.
    const Eigen::Vector3d point = centroid + c.cross(cbar) / c.squaredNorm();
    double squares = 0;
    std::size_t count = 0;
    for (const Sample& s : samples) {
        const Eigen::Vector3d across = s.normal.cross(axis);
        if (across.norm() < 1e-6) {
            continue;  // a normal along the axis meets it nowhere in particular
        }
        const double d = (s.position - point).dot(across) / across.norm();
        squares += d * d;
        ++count;
    }
    fit.rmsM = count ? std::sqrt(squares / double(count)) : std::numeric_limits<double>::infinity();
    fit.direction = {axis.x(), axis.y(), axis.z()};
    fit.point = {point.x(), point.y(), point.z()};
    fit.valid = count > 100;
    return fit;
}

SurfaceMesh makeSurfaceMesh(const scan::ProjectorSurface& surface,
                            const proto::PinholeCamera& projector,
                            const SurfaceMeshOptions& options) {
    const int w = surface.width, h = surface.height;
    const auto at = [&](int i, int j) { return static_cast<std::size_t>(j) * w + i; };
    const auto valid = [&](int i, int j) {
        return i >= 0 && j >= 0 && i < w && j < h && !std::isnan(surface.position[3 * at(i, j)]) &&
               !std::isnan(surface.normal[3 * at(i, j)]);
    };
    int left = w, right = -1, top = h, bottom = -1;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            if (valid(i, j)) {
                left = std::min(left, i);
                right = std::max(right, i);
                top = std::min(top, j);
                bottom = std::max(bottom, j);
            }
        }
    }
    if (right - left < 16 || bottom - top < 16) {
        throw common::InputError("the scan measured too little to make a surface of (" +
                                 std::to_string(surface.measured) + " projector pixels)");
    }
    SurfaceMesh result;
    result.step = options.step > 0 ? options.step : std::max(1, (right - left) / kTargetVertices);
    const int step = result.step;
    result.axis = fitRevolutionAxis(surface);
    const bool cylindrical = result.axis.valid && result.axis.rmsM <= options.maxAxisResidual &&
                             std::abs(result.axis.pitch) <= kMaxPitch;
    result.chart = cylindrical ? SurfaceChart::kCylindrical : SurfaceChart::kProjector;

    // The object frame in the camera's: y up (against the camera's image y), z towards the
    // projector across y, x = y × z.
    const proto::Vec3d c = projector.center();
    const Eigen::Vector3d projectorCentre(c.x, c.y, c.z);
    const std::vector<Sample> samples = measured(surface, kAxisSamples);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Sample& s : samples) {
        centroid += s.position;
    }
    centroid /= double(samples.size());
    Eigen::Vector3d y = -Eigen::Vector3d::UnitY();
    Eigen::Vector3d origin = centroid;
    if (cylindrical) {
        Eigen::Vector3d axis(result.axis.direction[0], result.axis.direction[1],
                             result.axis.direction[2]);
        if (axis.dot(y) < 0) {
            axis = -axis;
        }
        y = axis;
        const Eigen::Vector3d point(result.axis.point[0], result.axis.point[1],
                                    result.axis.point[2]);
        double lowest = std::numeric_limits<double>::infinity();
        for (const Sample& s : samples) {
            lowest = std::min(lowest, (s.position - point).dot(y));
        }
        origin = point + lowest * y;
    }
    Eigen::Vector3d z = projectorCentre - origin;
    z -= z.dot(y) * y;
    if (!cylindrical) {
        // The projector chart: z towards the projector, y the camera's up made perpendicular.
        z = (projectorCentre - centroid).normalized();
        y = (y - y.dot(z) * z).normalized();
    }
    z.normalize();
    const Eigen::Vector3d x = y.cross(z);
    Eigen::Matrix3d R;
    R.col(0) = x;
    R.col(1) = y;
    R.col(2) = z;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            result.objectToCamera.R[static_cast<std::size_t>(3 * i + k)] = R(i, k);
        }
        result.objectToCamera.t[static_cast<std::size_t>(i)] = origin(i);
    }

    // Vertices at the grid's nodes, in the object frame.
    const int columns = (right - left) / step + 1, rows = (bottom - top) / step + 1;
    std::vector<std::int64_t> vertexOf(static_cast<std::size_t>(columns) * rows, -1);
    std::vector<Eigen::Vector3d> local;
    std::vector<std::pair<int, int>> grid;  // each vertex's (column, row) in the grid
    double heightLow = std::numeric_limits<double>::infinity(), heightHigh = -heightLow, radius = 0;
    scene::ScreenMesh& mesh = result.mesh;
    for (int r = 0; r < rows; ++r) {
        for (int k = 0; k < columns; ++k) {
            const int i = left + k * step, j = top + r * step;
            if (!valid(i, j)) {
                continue;
            }
            const std::size_t p = at(i, j);
            const Eigen::Vector3d position(surface.position[3 * p], surface.position[3 * p + 1],
                                           surface.position[3 * p + 2]);
            const Eigen::Vector3d normal(surface.normal[3 * p], surface.normal[3 * p + 1],
                                         surface.normal[3 * p + 2]);
            const Eigen::Vector3d q = R.transpose() * (position - origin);
            const Eigen::Vector3d n = (R.transpose() * normal).normalized();
            vertexOf[static_cast<std::size_t>(r) * columns + k] =
                static_cast<std::int64_t>(local.size());
            local.push_back(q);
            grid.emplace_back(k, r);
            mesh.positions.push_back({float(q.x()), float(q.y()), float(q.z())});
            mesh.normals.push_back({float(n.x()), float(n.y()), float(n.z())});
            heightLow = std::min(heightLow, q.y());
            heightHigh = std::max(heightHigh, q.y());
            radius += std::hypot(q.x(), q.z());
        }
    }
    radius /= double(local.size());
    // Texture coordinates (OBJ: v up).
    const double span = std::max(right - left, bottom - top);
    for (std::size_t v = 0; v < local.size(); ++v) {
        const Eigen::Vector3d& q = local[v];
        if (cylindrical) {
            // u once around (the front, +z, at ½; the seam at the back), v along the height in
            // the same metres per unit where the radius is the mean radius: square texels there.
            const double around = 2 * kPi * radius;
            mesh.uvs.push_back(
                {float(0.5 + std::atan2(q.x(), q.z()) / (2 * kPi)),
                 float((q.y() - heightLow) / std::max(around, heightHigh - heightLow))});
        } else {
            // The projector's image, its measured part scaled into the unit square.
            mesh.uvs.push_back(
                {float(grid[v].first * step / span), float(1.0 - grid[v].second * step / span)});
        }
    }

    // Triangles of the grid, where the surface is continuous; wound to agree with the normals.
    const double focal = std::sqrt(projector.K[0] * projector.K[4]);
    const auto addTriangle = [&](std::int64_t a, std::int64_t b, std::int64_t d) {
        if (a < 0 || b < 0 || d < 0) {
            return;
        }
        const Eigen::Vector3d& pa = local[static_cast<std::size_t>(a)];
        const Eigen::Vector3d& pb = local[static_cast<std::size_t>(b)];
        const Eigen::Vector3d& pd = local[static_cast<std::size_t>(d)];
        const double depth = (R * pa + origin - projectorCentre).norm();
        const double longest = std::max({(pa - pb).norm(), (pb - pd).norm(), (pd - pa).norm()});
        if (longest > options.maxEdgeSteps * step * depth / focal) {
            return;
        }
        if (cylindrical) {
            const float ua = mesh.uvs[static_cast<std::size_t>(a)].x;
            if (std::abs(ua - mesh.uvs[static_cast<std::size_t>(b)].x) > 0.5f ||
                std::abs(ua - mesh.uvs[static_cast<std::size_t>(d)].x) > 0.5f) {
                return;  // across the seam at the back
            }
        }
        const Eigen::Vector3d face = (pb - pa).cross(pd - pa);
        const proto::Vec3f& n = mesh.normals[static_cast<std::size_t>(a)];
        const bool agrees = face.dot(Eigen::Vector3d(n.x, n.y, n.z)) > 0;
        const auto ia = static_cast<std::uint32_t>(a), ib = static_cast<std::uint32_t>(b),
                   id = static_cast<std::uint32_t>(d);
        mesh.indices.insert(mesh.indices.end(), {ia, agrees ? ib : id, agrees ? id : ib});
    };
    for (int r = 0; r + 1 < rows; ++r) {
        for (int k = 0; k + 1 < columns; ++k) {
            const auto node = [&](int rr, int kk) {
                return vertexOf[static_cast<std::size_t>(rr) * columns + kk];
            };
            addTriangle(node(r, k), node(r, k + 1), node(r + 1, k));
            addTriangle(node(r, k + 1), node(r + 1, k + 1), node(r + 1, k));
        }
    }
    if (mesh.indices.size() < 3 * 32) {
        throw common::InputError("the scan's surface is too broken to make a mesh of (" +
                                 std::to_string(mesh.indices.size() / 3) + " triangles)");
    }
    scene::validateScreenMesh(mesh, "scan surface");
    return result;
}

void writeSurfaceMesh(const SurfaceMesh& surface, const std::filesystem::path& folder) {
    scene::writeScreenMeshObj(surface.mesh, folder / kSurfaceMeshFile);
    const nlohmann::json json = {
        {"chart", surfaceChartName(surface.chart)},
        {"object_to_camera", {{"R", surface.objectToCamera.R}, {"t", surface.objectToCamera.t}}},
        {"step", surface.step},
        {"axis",
         {{"valid", surface.axis.valid},
          {"direction", surface.axis.direction},
          {"point", surface.axis.point},
          {"rms_m", surface.axis.rmsM},
          {"pitch", surface.axis.pitch}}}};
    proto::writeTextFileAtomically(folder / kSurfaceFrameFile, json.dump(2) + "\n");
}

SurfaceMesh readSurfaceMesh(const std::filesystem::path& folder) {
    const std::filesystem::path framePath = folder / kSurfaceFrameFile;
    std::ifstream stream(framePath);
    if (!stream) {
        throw common::InputError(
            framePath, "missing (vpe scan writes it with " + std::string(kSurfaceMeshFile) + ")");
    }
    SurfaceMesh surface;
    try {
        nlohmann::json json;
        stream >> json;
        surface.objectToCamera.R = json.at("object_to_camera").at("R").get<std::array<double, 9>>();
        surface.objectToCamera.t = json.at("object_to_camera").at("t").get<std::array<double, 3>>();
        surface.chart = json.at("chart").get<std::string>() == "cylindrical"
                            ? SurfaceChart::kCylindrical
                            : SurfaceChart::kProjector;
        surface.step = json.at("step").get<int>();
        const nlohmann::json& axis = json.at("axis");
        surface.axis.valid = axis.at("valid").get<bool>();
        surface.axis.direction = axis.at("direction").get<std::array<double, 3>>();
        surface.axis.point = axis.at("point").get<std::array<double, 3>>();
        surface.axis.rmsM = axis.at("rms_m").get<double>();
        surface.axis.pitch = axis.at("pitch").get<double>();
    } catch (const nlohmann::json::exception& error) {
        throw common::InputError(framePath, std::string("not a surface frame: ") + error.what());
    }
    surface.mesh = scene::loadScreenMesh(folder / kSurfaceMeshFile);
    return surface;
}

}  // namespace vpe::registration
