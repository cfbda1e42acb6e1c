// SPDX-License-Identifier: MIT
// ProjectorBlend: the shares of several projectors on one object (see the header).
#include "vpe/bake/projector_blend.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/parallel_rows.h"
#include "vpe/renderer/cpu/projector_pixels.h"
#include "vpe/renderer/cpu/ray_caster.h"

namespace vpe::bake {

namespace {

using renderer::Vec3d;

// The weight every projector that reaches a point keeps at the very edge of its reach: a point
// only one projector reaches gets all of its light however close to that edge.
constexpr double kEdgeFloor = 1e-3;
// A step between neighbouring pixels' depths larger than this share of the depth is an edge of
// the projector's reach (an occluding contour: the far side is in the near side's shadow).
constexpr double kDepthStep = 0.02;
// How far short of a point a projector's ray stops when it tests for a shadow (metres).
constexpr double kShadowSlack = 0.003;
// The fade's width when not given: this share of the projector's shorter side.
constexpr double kDefaultFeatherShare = 0.08;

proto::Vec3d minus(const proto::Vec3d& a, const proto::Vec3d& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}

double smoothstep(double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
}

proto::Vec3d toDouble(const renderer::Vec3f& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// One projector: what each pixel sees, and the fade towards the edges of its reach.
struct ProjectorReach {
    renderer::ProjectorModel model;
    proto::Vec3d centre;
    int width = 0, height = 0;
    std::vector<std::optional<renderer::ProjectorPixel>> pixels;
    renderer::FloatImage fade;

    // The fade at a (sub)pixel position, bilinear; 0 outside the image.
    double fadeAt(double x, double y) const {
        if (!(x > -0.5 && y > -0.5 && x < width - 0.5 && y < height - 0.5)) {
            return 0;
        }
        const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, width - 1);
        const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, height - 1);
        const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
        const double fx = std::clamp(x - x0, 0.0, 1.0), fy = std::clamp(y - y0, 0.0, 1.0);
        const auto at = [&](int px, int py) { return static_cast<double>(fade.at(px, py)); };
        const double top = (1 - fx) * at(x0, y0) + fx * at(x1, y0);
        const double bottom = (1 - fx) * at(x0, y1) + fx * at(x1, y1);
        return (1 - fy) * top + fy * bottom;
    }
};

ProjectorReach traceReach(const renderer::RenderMesh& mesh, const renderer::ProjectorModel& model,
                          const BlendOptions& options) {
    ProjectorReach reach;
    reach.model = model;
    reach.centre = model.camera.center();
    reach.width = model.camera.width;
    reach.height = model.camera.height;
    const renderer::ProjectorPixels traced(mesh, model);
    const int w = reach.width, h = reach.height;
    reach.pixels.resize(static_cast<std::size_t>(w) * h);
    renderer::forEachRow(h, options.threads, [&](int y) {
        for (int x = 0; x < w; ++x) {
            auto pixel = traced.trace(x, y);
            if (pixel && pixel->irradianceScale > 0) {
                reach.pixels[static_cast<std::size_t>(y) * w + x] = std::move(pixel);
            }
        }
    });
    // Interior: reached, and so are its four neighbours at about the same depth. The distance
    // to the nearest pixel that is not (or to the image's border) is how far inside the reach
    // a pixel lies.
    const auto depth = [&](int x, int y) -> double {
        const auto& pixel = reach.pixels[static_cast<std::size_t>(y) * w + x];
        if (!pixel) {
            return -1;
        }
        const proto::Vec3d d = minus(pixel->point.position, reach.centre);
        return std::sqrt(proto::dot(d, d));
    };
    cv::Mat interior(h, w, CV_8U, cv::Scalar(0));
    renderer::forEachRow(h, options.threads, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const double here = depth(x, y);
            if (here < 0) {
                continue;
            }
            bool inside = true;
            const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
            for (const auto& [nx, ny] : neighbours) {
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) {
                    continue;  // the border is counted below
                }
                const double there = depth(nx, ny);
                if (there < 0 || std::fabs(there - here) > kDepthStep * here) {
                    inside = false;
                }
            }
            interior.at<std::uint8_t>(y, x) = inside ? 255 : 0;
        }
    });
    cv::Mat distance;
    cv::distanceTransform(interior, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    const double feather = options.featherPixels > 0
                               ? options.featherPixels
                               : kDefaultFeatherShare * static_cast<double>(std::min(w, h));
    reach.fade = renderer::FloatImage(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double toBorder = std::min({x + 0.5, w - 0.5 - x, y + 0.5, h - 0.5 - y});
            const double inside = std::min(static_cast<double>(distance.at<float>(y, x)), toBorder);
            reach.fade.at(x, y) = interior.at<std::uint8_t>(y, x)
                                      ? static_cast<float>(smoothstep(inside / feather))
                                      : 0.0f;
        }
    }
    return reach;
}

// Whether projector `reach` lights the point: in its image, facing it, nothing between.
bool reaches(const ProjectorReach& reach, const renderer::RayCaster& caster,
             const proto::Vec3d& point, const proto::Vec3d& normal,
             std::optional<proto::Vec2d>* pixel) {
    const proto::Vec3d toProjector = minus(reach.centre, point);
    if (!(proto::dot(normal, toProjector) > 0)) {
        return false;
    }
    const std::optional<proto::Vec2d> p = proto::projectToPixel(reach.model.camera, point);
    if (!p ||
        !(p->x > -0.5 && p->y > -0.5 && p->x < reach.width - 0.5 && p->y < reach.height - 0.5)) {
        return false;
    }
    // The segment from the projector to kShadowSlack short of the point: a grazing ray meets
    // the mesh's own facets around the point (their chords bulge past the smooth surface the
    // shading normal describes), which is no shadow; an occluder is centimetres away.
    const proto::Vec3d toPoint = minus(point, reach.centre);
    const double length = std::sqrt(proto::dot(toPoint, toPoint));
    if (caster.anyHit(reach.centre, toPoint, 0.0, 1.0 - kShadowSlack / length)) {
        return false;
    }
    if (pixel != nullptr) {
        *pixel = p;
    }
    return true;
}

}  // namespace

double projectionQuality(const renderer::ProjectorModel& projector, const proto::Vec3d& point,
                         const proto::Vec3d& normal) {
    const proto::Vec3d toProjector = minus(projector.camera.center(), point);
    const double distance = std::sqrt(proto::dot(toProjector, toProjector));
    const double cosine = distance > 0 ? proto::dot(normal, toProjector) / distance : 0;
    if (!(cosine > 0)) {
        return 0;
    }
    const double focal = std::sqrt(projector.camera.K[0] * projector.camera.K[4]);
    return cosine * cosine * (focal / distance) * (focal / distance);
}

ProjectorBlend blendProjectors(const renderer::RenderMesh& mesh,
                               const std::vector<renderer::ProjectorModel>& projectors,
                               const BlendOptions& options) {
    if (projectors.empty()) {
        throw std::invalid_argument("blendProjectors: no projector");
    }
    std::vector<ProjectorReach> reach;
    for (const renderer::ProjectorModel& projector : projectors) {
        reach.push_back(traceReach(mesh, projector, options));
    }
    const renderer::RayCaster caster(mesh);
    // The weight of projector j at a point (0 where it does not reach it); `own`: the point is
    // what j's own pixel sees, so it reaches it by construction (no ray: its depth test would
    // only add rounding).
    const auto weight = [&](std::size_t j, const proto::Vec3d& point, const proto::Vec3d& normal,
                            bool own) {
        std::optional<proto::Vec2d> pixel;
        if (own) {
            pixel = proto::projectToPixel(reach[j].model.camera, point);
            if (!pixel) {
                return 0.0;
            }
        } else if (!reaches(reach[j], caster, point, normal, &pixel)) {
            return 0.0;
        }
        return projectionQuality(reach[j].model, point, normal) *
               (kEdgeFloor + reach[j].fadeAt(pixel->x, pixel->y));
    };

    ProjectorBlend blend;
    for (std::size_t i = 0; i < reach.size(); ++i) {
        const int w = reach[i].width, h = reach[i].height;
        renderer::FloatImage share(w, h);
        renderer::forEachRow(h, options.threads, [&](int y) {
            for (int x = 0; x < w; ++x) {
                const auto& pixel = reach[i].pixels[static_cast<std::size_t>(y) * w + x];
                if (!pixel) {
                    continue;
                }
                const proto::Vec3d& point = pixel->point.position;
                const proto::Vec3d& normal = pixel->point.normal;
                const double own = weight(i, point, normal, true);
                double total = own;
                for (std::size_t j = 0; j < reach.size(); ++j) {
                    if (j != i) {
                        total += weight(j, point, normal, false);
                    }
                }
                share.at(x, y) = total > 0 ? static_cast<float>(own / total) : 1.0f;
            }
        });
        blend.shares.push_back(std::move(share));
    }

    // The surface in texture space: every texel centre inside a triangle, tested against every
    // projector; each triangle's area split by the share of its texels reached (its centroid
    // when it holds none).
    const int cw = options.coverageWidth, ch = options.coverageHeight;
    blend.reach = renderer::ScalarImage<std::uint8_t>(cw, ch, 255);
    const std::size_t triangles = mesh.indices.size() / 3;
    std::vector<double> area(triangles), unreached(triangles), overlap(triangles);
    const auto reachCount = [&](const proto::Vec3d& point, const proto::Vec3d& normal) {
        int count = 0;
        for (const ProjectorReach& r : reach) {
            // Two-sided: the side that faces the projector is lit.
            const proto::Vec3d toProjector = minus(r.centre, point);
            const proto::Vec3d facing = proto::dot(normal, toProjector) >= 0
                                            ? normal
                                            : proto::Vec3d{-normal.x, -normal.y, -normal.z};
            count += reaches(r, caster, point, facing, nullptr) ? 1 : 0;
        }
        return count;
    };
    std::vector<std::vector<std::pair<std::size_t, std::uint8_t>>> texels(triangles);
    renderer::forEachRow(static_cast<int>(triangles), options.threads, [&](int t) {
        const std::uint32_t* v = &mesh.indices[3 * static_cast<std::size_t>(t)];
        const proto::Vec3d p[3] = {toDouble(mesh.positions[v[0]]), toDouble(mesh.positions[v[1]]),
                                   toDouble(mesh.positions[v[2]])};
        const proto::Vec3d n[3] = {toDouble(mesh.normals[v[0]]), toDouble(mesh.normals[v[1]]),
                                   toDouble(mesh.normals[v[2]])};
        const proto::Vec3d e1 = minus(p[1], p[0]), e2 = minus(p[2], p[0]);
        const proto::Vec3d c{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z,
                             e1.x * e2.y - e1.y * e2.x};
        area[t] = 0.5 * std::sqrt(proto::dot(c, c));
        double tx[3], ty[3];
        for (int k = 0; k < 3; ++k) {
            tx[k] = static_cast<double>(mesh.uvs[v[k]].x) * cw - 0.5;
            ty[k] = (1.0 - static_cast<double>(mesh.uvs[v[k]].y)) * ch - 0.5;
        }
        const double det = (tx[1] - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (ty[1] - ty[0]);
        const auto at = [&](double b1, double b2) {
            const double b0 = 1 - b1 - b2;
            const proto::Vec3d point{b0 * p[0].x + b1 * p[1].x + b2 * p[2].x,
                                     b0 * p[0].y + b1 * p[1].y + b2 * p[2].y,
                                     b0 * p[0].z + b1 * p[1].z + b2 * p[2].z};
            const proto::Vec3d normal = proto::normalized(proto::Vec3d{
                b0 * n[0].x + b1 * n[1].x + b2 * n[2].x, b0 * n[0].y + b1 * n[1].y + b2 * n[2].y,
                b0 * n[0].z + b1 * n[1].z + b2 * n[2].z});
            return reachCount(point, normal);
        };
        int samples = 0, none = 0, several = 0;
        if (std::fabs(det) > 1e-12) {
            const int x0 =
                std::max(0, static_cast<int>(std::ceil(std::min({tx[0], tx[1], tx[2]}))));
            const int x1 =
                std::min(cw - 1, static_cast<int>(std::floor(std::max({tx[0], tx[1], tx[2]}))));
            const int y0 =
                std::max(0, static_cast<int>(std::ceil(std::min({ty[0], ty[1], ty[2]}))));
            const int y1 =
                std::min(ch - 1, static_cast<int>(std::floor(std::max({ty[0], ty[1], ty[2]}))));
            for (int y = y0; y <= y1; ++y) {
                for (int x = x0; x <= x1; ++x) {
                    const double b1 =
                        ((x - tx[0]) * (ty[2] - ty[0]) - (tx[2] - tx[0]) * (y - ty[0])) / det;
                    const double b2 =
                        ((tx[1] - tx[0]) * (y - ty[0]) - (x - tx[0]) * (ty[1] - ty[0])) / det;
                    if (b1 < 0 || b2 < 0 || b1 + b2 > 1) {
                        continue;
                    }
                    const int count = at(b1, b2);
                    ++samples;
                    none += count == 0 ? 1 : 0;
                    several += count >= 2 ? 1 : 0;
                    texels[t].push_back({static_cast<std::size_t>(y) * cw + x,
                                         static_cast<std::uint8_t>(std::min(count, 254))});
                }
            }
        }
        if (samples == 0) {
            const int count = at(1.0 / 3, 1.0 / 3);
            samples = 1;
            none = count == 0 ? 1 : 0;
            several = count >= 2 ? 1 : 0;
        }
        unreached[t] = area[t] * none / samples;
        overlap[t] = area[t] * several / samples;
    });
    double total = 0, none = 0, several = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
        total += area[t];
        none += unreached[t];
        several += overlap[t];
        for (const auto& [texel, count] : texels[t]) {
            blend.reach.values[texel] = count;
        }
    }
    blend.unreachedShare = total > 0 ? none / total : 0;
    blend.overlapShare = total > 0 ? several / total : 0;
    return blend;
}

}  // namespace vpe::bake
