// SPDX-License-Identifier: MIT
// Triangulation into the projector's image, and normals from the measured surface.
#include "vpe/scan/projector_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"

namespace vpe::scan {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Eigen::Vector3d eigen(const proto::Vec3d& v) {
    return {v.x, v.y, v.z};
}

// Decoded camera pixels: the 3D point each one triangulates to (to judge triangles) and its
// undistorted normalized coordinates (to interpolate camera rays inside them).
struct CameraVertex {
    float idealA = 0, idealB = 0;
    float x = 0, y = 0, z = 0;  // triangulated point, camera frame
    bool valid = false;
};

// Calls visit(di, dj, q) for every projector pixel q = (i + di, j + dj) of the square window of
// `radius` around (i, j) whose position is known, row by row: the neighbours the completion's
// depth fit and the normals' principal axes both take.
template <typename Visit>
void forEachKnownNeighbour(const std::vector<float>& position, int width, int height, int i, int j,
                           int radius, Visit visit) {
    for (int dj = -radius; dj <= radius; ++dj) {
        for (int di = -radius; di <= radius; ++di) {
            const int x = i + di, y = j + dj;
            if (x < 0 || y < 0 || x >= width || y >= height) {
                continue;
            }
            const std::size_t q = static_cast<std::size_t>(y) * width + x;
            if (std::isnan(position[3 * q])) {
                continue;
            }
            visit(di, dj, q);
        }
    }
}

}  // namespace

RayMeeting closestApproach(const proto::Vec3d& o1, const proto::Vec3d& d1, const proto::Vec3d& o2,
                           const proto::Vec3d& d2) {
    const Eigen::Vector3d p1 = eigen(o1), u = eigen(d1), p2 = eigen(o2), v = eigen(d2);
    const Eigen::Vector3d w = p1 - p2;
    const double a = u.dot(u), b = u.dot(v), c = v.dot(v), d = u.dot(w), e = v.dot(w);
    const double denominator = a * c - b * b;
    RayMeeting meeting;
    if (!(denominator > 1e-14 * a * c)) {
        return meeting;
    }
    const double s = (b * e - c * d) / denominator;
    const double t = (a * e - b * d) / denominator;
    const Eigen::Vector3d q1 = p1 + s * u, q2 = p2 + t * v;
    const Eigen::Vector3d mid = 0.5 * (q1 + q2);
    meeting.point = {mid.x(), mid.y(), mid.z()};
    meeting.gap = (q1 - q2).norm();
    meeting.valid = s > 0 && t > 0;
    return meeting;
}

ProjectorSurface triangulateScan(const structured_light::DecodedScan& scan, const ProcamRig& rig,
                                 const TriangulationOptions& options) {
    if (rig.projector.width != scan.projectorWidth ||
        rig.projector.height != scan.projectorHeight) {
        throw common::InputError(
            "the calibration's projector is " + std::to_string(rig.projector.width) + "x" +
            std::to_string(rig.projector.height) + ", the scan's " +
            std::to_string(scan.projectorWidth) + "x" + std::to_string(scan.projectorHeight));
    }
    if (rig.camera.width != scan.width || rig.camera.height != scan.height) {
        throw common::InputError("the calibration's camera is " + std::to_string(rig.camera.width) +
                                 "x" + std::to_string(rig.camera.height) + ", the scan's images " +
                                 std::to_string(scan.width) + "x" + std::to_string(scan.height));
    }
    const unsigned threads = common::resolveThreadCount(options.threads);
    const int cw = scan.width, ch = scan.height;
    const int pw = scan.projectorWidth, ph = scan.projectorHeight;
    const proto::Vec3d projectorCentre = rig.projector.center();
    const proto::Vec3d origin{0, 0, 0};
    const double focal = std::sqrt(rig.camera.K[0] * rig.camera.K[4]);

    // Every decoded camera pixel on its own: its ray and the point it meets the projector's at.
    std::vector<CameraVertex> vertices(static_cast<std::size_t>(cw) * ch);
    common::parallelFor(vertices.size(), 4096, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t q = begin; q < end; ++q) {
            if (std::isnan(scan.projectorX[q]) ||
                !(double(scan.precision[q]) <= options.maxSigma)) {
                continue;
            }
            const proto::Vec2d pixel{double(q % static_cast<std::size_t>(cw)),
                                     double(q / static_cast<std::size_t>(cw))};
            const proto::Vec2d ideal = proto::undistortNormalized(
                rig.camera.distortion, proto::pixelToNormalized(rig.camera, pixel));
            const RayMeeting meeting = closestApproach(
                origin, {ideal.x, ideal.y, 1.0}, projectorCentre,
                proto::pixelRayDirection(rig.projector,
                                         {double(scan.projectorX[q]), double(scan.projectorY[q])}));
            if (!meeting.valid || meeting.gap > options.maxRayGap) {
                continue;
            }
            CameraVertex& v = vertices[q];
            v.idealA = float(ideal.x);
            v.idealB = float(ideal.y);
            v.x = float(meeting.point.x);
            v.y = float(meeting.point.y);
            v.z = float(meeting.point.z);
            v.valid = true;
        }
    });

    ProjectorSurface surface;
    surface.width = pw;
    surface.height = ph;
    const std::size_t projectorPixels = static_cast<std::size_t>(pw) * ph;
    surface.position.assign(projectorPixels * 3, kNaN);
    surface.normal.assign(projectorPixels * 3, kNaN);
    surface.confidence.assign(projectorPixels, kNaN);
    surface.rayGap.assign(projectorPixels, kNaN);
    surface.cameraU.assign(projectorPixels, kNaN);
    surface.cameraV.assign(projectorPixels, kNaN);
    std::vector<float> depth(projectorPixels, std::numeric_limits<float>::infinity());

    // The orientation most triangles have from camera to projector image: a triangle drawn the
    // other way round is folded over (an occlusion edge) and is not a surface.
    long orientation = 0;
    const auto corner = [&](int x, int y) { return static_cast<std::size_t>(y) * cw + x; };
    const auto signedArea = [&](std::size_t a, std::size_t b, std::size_t c) {
        const double ax = scan.projectorX[a], ay = scan.projectorY[a];
        return (double(scan.projectorX[b]) - ax) * (double(scan.projectorY[c]) - ay) -
               (double(scan.projectorX[c]) - ax) * (double(scan.projectorY[b]) - ay);
    };
    for (int y = 0; y + 1 < ch; ++y) {
        for (int x = 0; x + 1 < cw; ++x) {
            const std::size_t a = corner(x, y), b = corner(x + 1, y), c = corner(x, y + 1);
            if (vertices[a].valid && vertices[b].valid && vertices[c].valid) {
                orientation += signedArea(a, b, c) > 0 ? 1 : -1;
            }
        }
    }
    const double sense = orientation >= 0 ? 1.0 : -1.0;

    const auto drawTriangle = [&](std::size_t a, std::size_t b, std::size_t c) {
        const CameraVertex* v[3] = {&vertices[a], &vertices[b], &vertices[c]};
        if (!v[0]->valid || !v[1]->valid || !v[2]->valid) {
            return;
        }
        const double area = signedArea(a, b, c) * sense;
        if (!(area > 0)) {
            return;
        }
        // A surface, not a jump: every edge within a few footprints of a camera pixel.
        double longest = 0, nearest = std::numeric_limits<double>::infinity();
        for (int e = 0; e < 3; ++e) {
            const CameraVertex& p = *v[e];
            const CameraVertex& q = *v[(e + 1) % 3];
            longest = std::max(longest,
                               std::hypot(double(p.x - q.x), double(p.y - q.y), double(p.z - q.z)));
            nearest = std::min(nearest, double(p.z));
        }
        if (longest > options.maxEdgeFootprints * nearest / focal) {
            return;
        }
        const std::size_t ids[3] = {a, b, c};
        double px[3], py[3];
        for (int k = 0; k < 3; ++k) {
            px[k] = scan.projectorX[ids[k]];
            py[k] = scan.projectorY[ids[k]];
        }
        const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({px[0], px[1], px[2]}))));
        const int x1 =
            std::min(pw - 1, static_cast<int>(std::floor(std::max({px[0], px[1], px[2]}))));
        const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({py[0], py[1], py[2]}))));
        const int y1 =
            std::min(ph - 1, static_cast<int>(std::floor(std::max({py[0], py[1], py[2]}))));
        const double det = (px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]);
        for (int j = y0; j <= y1; ++j) {
            for (int i = x0; i <= x1; ++i) {
                const double b1 =
                    ((i - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (j - py[0])) / det;
                const double b2 =
                    ((px[1] - px[0]) * (j - py[0]) - (i - px[0]) * (py[1] - py[0])) / det;
                const double b0 = 1 - b1 - b2;
                if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) {
                    continue;
                }
                const double ia = b0 * double(v[0]->idealA) + b1 * double(v[1]->idealA) +
                                  b2 * double(v[2]->idealA);
                const double ib = b0 * double(v[0]->idealB) + b1 * double(v[1]->idealB) +
                                  b2 * double(v[2]->idealB);
                const RayMeeting meeting = closestApproach(
                    origin, {ia, ib, 1.0}, projectorCentre,
                    proto::pixelRayDirection(rig.projector, {double(i), double(j)}));
                if (!meeting.valid || meeting.gap > options.maxRayGap) {
                    continue;
                }
                const std::size_t p = static_cast<std::size_t>(j) * pw + i;
                const proto::Vec3d toPoint{meeting.point.x - projectorCentre.x,
                                           meeting.point.y - projectorCentre.y,
                                           meeting.point.z - projectorCentre.z};
                const auto distance = static_cast<float>(std::sqrt(proto::dot(toPoint, toPoint)));
                if (!(distance < depth[p])) {
                    continue;  // the projector lights the nearest surface along its ray
                }
                depth[p] = distance;
                surface.position[3 * p] = float(meeting.point.x);
                surface.position[3 * p + 1] = float(meeting.point.y);
                surface.position[3 * p + 2] = float(meeting.point.z);
                surface.rayGap[p] = float(meeting.gap);
                float sigma = 0;
                for (int k = 0; k < 3; ++k) {
                    sigma = std::max(sigma, scan.precision[ids[k]]);
                }
                surface.confidence[p] = std::clamp(1.0f - 2.0f * sigma, 0.0f, 1.0f);
                const double column = double(a % static_cast<std::size_t>(cw)),
                             row = double(a / static_cast<std::size_t>(cw));
                const double columns[3] = {column, double(b % static_cast<std::size_t>(cw)),
                                           double(c % static_cast<std::size_t>(cw))};
                const double rows[3] = {row, double(b / static_cast<std::size_t>(cw)),
                                        double(c / static_cast<std::size_t>(cw))};
                surface.cameraU[p] = float(b0 * columns[0] + b1 * columns[1] + b2 * columns[2]);
                surface.cameraV[p] = float(b0 * rows[0] + b1 * rows[1] + b2 * rows[2]);
            }
        }
    };
    for (int y = 0; y + 1 < ch; ++y) {
        for (int x = 0; x + 1 < cw; ++x) {
            drawTriangle(corner(x, y), corner(x + 1, y), corner(x, y + 1));
            drawTriangle(corner(x + 1, y), corner(x + 1, y + 1), corner(x, y + 1));
        }
    }

    // Completion near the camera's silhouette (see TriangulationOptions::fillRadius).
    if (options.fillRadius > 0) {
        const int r = options.fillRadius + 1;
        std::vector<float> filled = surface.position;
        std::vector<float> filledConfidence = surface.confidence;
        std::vector<std::uint8_t> isFilled(projectorPixels, 0);
        common::parallelFor(
            projectorPixels, 2048, threads, [&](std::size_t begin, std::size_t end) {
                for (std::size_t p = begin; p < end; ++p) {
                    if (!std::isnan(surface.position[3 * p])) {
                        continue;
                    }
                    const int i = static_cast<int>(p % static_cast<std::size_t>(pw));
                    const int j = static_cast<int>(p / static_cast<std::size_t>(pw));
                    // Least squares of the distance along the ray, t = a + b·di + c·dj.
                    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
                    Eigen::Vector3d right = Eigen::Vector3d::Zero();
                    double squares = 0;
                    int count = 0, nearest = r + 1;
                    float confidence = 1;
                    forEachKnownNeighbour(
                        surface.position, pw, ph, i, j, r, [&](int di, int dj, std::size_t q) {
                            const double t =
                                std::hypot(double(surface.position[3 * q]) - projectorCentre.x,
                                           double(surface.position[3 * q + 1]) - projectorCentre.y,
                                           double(surface.position[3 * q + 2]) - projectorCentre.z);
                            const Eigen::Vector3d row(1.0, di, dj);
                            normal += row * row.transpose();
                            right += row * t;
                            squares += t * t;
                            ++count;
                            nearest = std::min(nearest, std::max(std::abs(di), std::abs(dj)));
                            confidence = std::min(confidence, surface.confidence[q]);
                        });
                    if (count < 12 || nearest > options.fillRadius) {
                        continue;
                    }
                    const Eigen::Vector3d plane = normal.ldlt().solve(right);
                    // The neighbours must lie on their plane (a smooth patch, not a step or noise).
                    const double residual =
                        std::sqrt(std::max(0.0, (squares - plane.dot(right)) / count));
                    if (residual > options.maxFillResidual) {
                        continue;
                    }
                    const proto::Vec3d ray = proto::normalized(
                        proto::pixelRayDirection(rig.projector, {double(i), double(j)}));
                    const proto::Vec3d point{projectorCentre.x + plane[0] * ray.x,
                                             projectorCentre.y + plane[0] * ray.y,
                                             projectorCentre.z + plane[0] * ray.z};
                    // The camera must see projector light where the point falls: otherwise the
                    // surface has ended (the camera's silhouette against the room).
                    const auto seen = proto::projectToPixel(rig.camera, point);
                    if (!seen) {
                        continue;
                    }
                    const int u = static_cast<int>(std::lround(seen->x));
                    const int v = static_cast<int>(std::lround(seen->y));
                    if (u < 0 || v < 0 || u >= cw || v >= ch ||
                        double(scan.direct[static_cast<std::size_t>(v) * cw + u]) <
                            options.minDirect) {
                        continue;
                    }
                    filled[3 * p] = float(point.x);
                    filled[3 * p + 1] = float(point.y);
                    filled[3 * p + 2] = float(point.z);
                    filledConfidence[p] = 0.5f * confidence;
                    isFilled[p] = 1;
                }
            });
        surface.position = std::move(filled);
        surface.confidence = std::move(filledConfidence);
        for (const std::uint8_t f : isFilled) {
            surface.completed += f;
        }
    }

    // Normals: the plane through the measured points of a (2r + 1)² window (principal axes),
    // turned towards the projector.
    const int r = options.normalRadius;
    common::parallelFor(projectorPixels, 2048, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) {
            if (std::isnan(surface.position[3 * p])) {
                continue;
            }
            const int i = static_cast<int>(p % static_cast<std::size_t>(pw));
            const int j = static_cast<int>(p / static_cast<std::size_t>(pw));
            const Eigen::Vector3d centre(surface.position[3 * p], surface.position[3 * p + 1],
                                         surface.position[3 * p + 2]);
            Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            int count = 0;
            forEachKnownNeighbour(surface.position, pw, ph, i, j, r, [&](int, int, std::size_t q) {
                const Eigen::Vector3d d =
                    Eigen::Vector3d(surface.position[3 * q], surface.position[3 * q + 1],
                                    surface.position[3 * q + 2]) -
                    centre;
                sum += d;
                scatter += d * d.transpose();
                ++count;
            });
            if (count < 6) {
                continue;
            }
            const Eigen::Vector3d mean = sum / count;
            scatter = scatter / count - mean * mean.transpose();
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
            Eigen::Vector3d n = solver.eigenvectors().col(0);
            const Eigen::Vector3d toProjector = eigen(projectorCentre) - centre;
            if (n.dot(toProjector) < 0) {
                n = -n;
            }
            surface.normal[3 * p] = float(n.x());
            surface.normal[3 * p + 1] = float(n.y());
            surface.normal[3 * p + 2] = float(n.z());
        }
    });
    for (std::size_t p = 0; p < projectorPixels; ++p) {
        if (std::isnan(surface.normal[3 * p])) {
            // Too few neighbours to know its orientation: not a usable measurement.
            surface.position[3 * p] = surface.position[3 * p + 1] = surface.position[3 * p + 2] =
                kNaN;
            surface.confidence[p] = surface.rayGap[p] = surface.cameraU[p] = surface.cameraV[p] =
                kNaN;
        } else {
            ++surface.measured;
        }
    }
    if (surface.measured == 0) {
        throw common::InputError(
            "nothing could be triangulated: the calibration does not match the scan "
            "(rays do not meet), or nothing was decoded");
    }
    return surface;
}

}  // namespace vpe::scan
