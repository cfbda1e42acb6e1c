// SPDX-License-Identifier: MIT
// Truth and pipeline rendered for each view, compared as people see them.
#include "vpe/transfer/transfer_fidelity.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "vpe/common/input_error.h"
#include "vpe/common/progress_bar.h"
#include "vpe/image/image_file.h"
#include "vpe/image/image_metrics.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/detail_normal.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/parallel_rows.h"
#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/surface_point.h"
#include "vpe/renderer/cpu/visitor_view.h"
#include "vpe/transfer/synthetic_truth.h"

namespace vpe::transfer {

namespace {

using renderer::Vec3d;

// Mean angle between the bundle's relief and the truth's, over the texels (at their centres).
double reliefError(const renderer::BundleScene& bundleScene, const SyntheticTruth& truth) {
    const renderer::RenderScene scene = bundleScene.scene({}, {0, 0, 1});
    const int w = truth.width(), h = truth.height();
    double sum = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const renderer::Vec2d uv{(x + 0.5) / w, 1.0 - (y + 0.5) / h};
            const proto::Vec3d a =
                proto::normalized(renderer::sampleDetailNormal(scene.material, uv));
            const std::size_t t = static_cast<std::size_t>(y) * w + x;
            const proto::Vec3d b = proto::detailNormalFromXy<double>(
                truth.detailNormals()[2 * t], truth.detailNormals()[2 * t + 1]);
            sum += std::acos(std::clamp(proto::dot(a, b), -1.0, 1.0));
        }
    }
    return sum / (static_cast<double>(w) * h) * 180.0 / std::numbers::pi;
}

}  // namespace

// An exposure that puts the 99th percentile of the lit pixels' brightest channel at 0.8 (as
// `vpe render` previews do), from the truth, for both pictures.
double truthExposure(const renderer::RgbImage& image, const renderer::MaskImage& coverage) {
    std::vector<float> values;
    for (std::size_t p = 0; p < coverage.values.size(); ++p) {
        const float v =
            std::max({image.values[3 * p], image.values[3 * p + 1], image.values[3 * p + 2]});
        if (coverage.values[p] && v > 0) {
            values.push_back(v);
        }
    }
    if (values.empty()) {
        return 1.0;
    }
    const auto at =
        values.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), at, values.end());
    return 0.8 / static_cast<double>(*at);
}

// The truth seen by the camera: the pipeline's direct view with the true material.
renderer::RgbImage renderTruthView(const renderer::RenderScene& scene, const SyntheticTruth& truth,
                                   const proto::PinholeCamera& camera, int threads,
                                   renderer::RgbImage* viewDependent) {
    renderer::RgbImage image(camera.width, camera.height);
    if (viewDependent != nullptr) {
        *viewDependent = renderer::RgbImage(camera.width, camera.height);
    }
    const renderer::RayCaster caster(scene.mesh);
    const proto::Vec3d eye = camera.center();
    renderer::forEachRow(camera.height, threads, [&](int y) {
        for (int x = 0; x < camera.width; ++x) {
            const proto::Vec3d ray = proto::pixelRayDirection(camera, {double(x), double(y)});
            const auto hit = caster.closestHit(eye, ray);
            if (!hit) {
                continue;
            }
            const renderer::SurfacePoint point = renderer::surfacePoint(scene.mesh, eye, ray, *hit);
            const std::array<double, 3> radiance = truth.radiance(point, scene.light, eye);
            float* out = image.pixel(x, y);
            for (std::size_t c = 0; c < 3; ++c) {
                out[c] = static_cast<float>(std::max(radiance[c], 0.0));
            }
            if (viewDependent != nullptr) {
                const std::array<double, 3> part =
                    truth.viewDependentRadiance(point, scene.light, eye);
                float* to = viewDependent->pixel(x, y);
                for (std::size_t c = 0; c < 3; ++c) {
                    to[c] = static_cast<float>(part[c]);
                }
            }
        }
    });
    return image;
}

proto::Vec3d directionAt(double azimuthDegrees, double elevationDegrees) {
    const double a = azimuthDegrees * std::numbers::pi / 180.0;
    const double e = elevationDegrees * std::numbers::pi / 180.0;
    return {std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e)};
}

MeshBounds meshBounds(const std::vector<float>& positions) {
    MeshBounds bounds{{1e30, 1e30, 1e30}, {-1e30, -1e30, -1e30}};
    proto::Vec3d& lower = bounds.lower;
    proto::Vec3d& upper = bounds.upper;
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        lower = {std::min(lower.x, double(positions[i])),
                 std::min(lower.y, double(positions[i + 1])),
                 std::min(lower.z, double(positions[i + 2]))};
        upper = {std::max(upper.x, double(positions[i])),
                 std::max(upper.y, double(positions[i + 1])),
                 std::max(upper.z, double(positions[i + 2]))};
    }
    return bounds;
}

std::vector<TransferView> transferViews(const proto::Vec3d& lower, const proto::Vec3d& upper) {
    const proto::Vec3d centre{0.5 * (lower.x + upper.x), 0.5 * (lower.y + upper.y),
                              0.5 * (lower.z + upper.z)};
    const double distance = 4.0 * (upper.y - lower.y);
    const auto at = [&](double azimuth, double elevation) {
        const proto::Vec3d d = directionAt(azimuth, elevation);
        return proto::Vec3d{centre.x + distance * d.x, centre.y + distance * d.y,
                            centre.z + distance * d.z};
    };
    // The paper's rig lit from −10° to 50° of elevation within ±81° of the camera: "key" is
    // inside that range (a control), every other view leaves it.
    return {
        {"key", "front view, light up and to the left (inside the capture's range)", at(0, 0),
         at(-35, 30)},
        {"grazing-side", "front view, light from the side, 5° above the horizon", at(0, 0),
         at(85, 5)},
        {"grazing-top", "front view, light from 80° above: grazing on the wall", at(0, 0),
         at(0, 80)},
        {"below", "front view, light from 50° below", at(0, 0), at(20, -50)},
        {"side-view", "view from the side, light from the front: grazing for the viewer",
         at(90, 10), at(0, 20)},
        {"back", "view around the back (the texture's seam), light behind the viewer", at(180, 10),
         at(150, 35)},
        {"backlit", "front view, light behind the vase's side: lit from behind, at grazing",
         at(0, 0), at(125, 20)},
        {"above", "view from 55° above, light low from the left", at(30, 55), at(-90, 25)},
    };
}

TransferReport measureTransferFidelity(const TransferOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const SyntheticTruth truth(options.capture);
    proto::BundleFile file = proto::BundleFile::open(options.bundle);
    const proto::BundleView& bundle = file.view();
    if (bundle.textureWidth() != truth.width() || bundle.textureHeight() != truth.height()) {
        throw common::InputError(
            options.bundle, "textures of " + std::to_string(bundle.textureWidth()) + " x " +
                                std::to_string(bundle.textureHeight()) +
                                ", the capture's truth is " + std::to_string(truth.width()) +
                                " x " + std::to_string(truth.height()) +
                                " (bake the fitted model itself: vpe bake --texture MODEL.exr)");
    }
    const renderer::BundleScene bundleScene(bundle, "");
    TransferReport report;
    report.textureWidth = truth.width();
    report.textureHeight = truth.height();
    for (const proto::RegionView& region : bundle.regions()) {
        report.relief = report.relief || !region.coefficients.detailNormals.empty();
    }

    // With the truth's relief substituted, the relief rendered is the truth's.
    report.reliefErrorDegrees = options.trueRelief ? 0.0 : reliefError(bundleScene, truth);

    const MeshBounds bounds =
        meshBounds({bundle.mesh().positions.begin(), bundle.mesh().positions.end()});
    const proto::Vec3d centre = bounds.centre();
    std::vector<TransferView> views;
    for (const TransferView& view : transferViews(bounds.lower, bounds.upper)) {
        if (options.views.empty() || std::find(options.views.begin(), options.views.end(),
                                               view.name) != options.views.end()) {
            views.push_back(view);
        }
    }
    for (const std::string& name : options.views) {
        if (std::none_of(views.begin(), views.end(),
                         [&name](const TransferView& v) { return v.name == name; })) {
            throw common::InputError("--views: no view '" + name + "'");
        }
    }
    if (!options.out.empty()) {
        std::filesystem::create_directories(options.out);
    }

    common::ProgressBar progress("transfer", views.size());
    for (const TransferView& view : views) {
        renderer::VirtualLight light;
        light.position = view.light;
        renderer::RenderScene scene = bundleScene.scene(light, view.viewer);
        if (options.trueRelief) {
            for (renderer::MaterialRegion& region : scene.material.regions) {
                region.detailNormals = truth.detailNormals();
            }
        }
        const proto::PinholeCamera camera = proto::cameraLookingAt(
            options.viewWidth, options.viewHeight, options.fovDegrees, view.viewer, centre);
        renderer::RenderOptions renderOptions;
        renderOptions.threads = options.threads;
        const renderer::DirectView pipeline =
            renderer::renderDirectView(scene, camera, renderOptions);
        const renderer::RgbImage truthImage =
            renderTruthView(scene, truth, camera, options.threads);

        ViewFidelity fidelity;
        fidelity.name = view.name;
        fidelity.exposure = truthExposure(truthImage, pipeline.coverage);
        const image::Rgb8Image a =
            image::toSrgb8(truthImage.values, camera.width, camera.height, fidelity.exposure);
        const image::Rgb8Image b = image::toSrgb8(pipeline.radiance.values, camera.width,
                                                  camera.height, fidelity.exposure);
        std::vector<std::uint8_t> lit(pipeline.coverage.values.size(), 0);
        std::size_t litPixels = 0;
        for (std::size_t p = 0; p < lit.size(); ++p) {
            if (!pipeline.coverage.values[p]) {
                continue;
            }
            ++fidelity.objectPixels;
            for (std::size_t c = 0; c < 3; ++c) {
                lit[p] = lit[p] || a.values[3 * p + c] > 0 || b.values[3 * p + c] > 0;
            }
            litPixels += lit[p];
        }
        fidelity.litShare = fidelity.objectPixels ? static_cast<double>(litPixels) /
                                                        static_cast<double>(fidelity.objectPixels)
                                                  : 0.0;
        fidelity.psnr = image::psnr(a, b, lit);
        fidelity.ssim = image::meanSsim(a, b, lit);
        fidelity.psnrObject = image::psnr(a, b, pipeline.coverage.values);
        report.views.push_back(fidelity);

        if (!options.out.empty()) {
            const std::filesystem::path base = options.out / view.name;
            image::writeImage8(base.string() + "-truth.png", a.width, a.height, 3, a.values);
            image::writeImage8(base.string() + "-pipeline.png", b.width, b.height, 3, b.values);
            // |truth − pipeline| of the 8-bit pictures, ×4.
            std::vector<std::uint8_t> difference(a.values.size());
            for (std::size_t i = 0; i < difference.size(); ++i) {
                difference[i] = static_cast<std::uint8_t>(
                    std::min(255, 4 * std::abs(int(a.values[i]) - int(b.values[i]))));
            }
            image::writeImage8(base.string() + "-difference.png", a.width, a.height, 3, difference);
        }
        progress.advance();
    }
    progress.finish();

    double psnrSum = 0, ssimSum = 0;
    report.worstPsnr = std::numeric_limits<double>::infinity();
    for (const ViewFidelity& v : report.views) {
        psnrSum += v.psnr;
        ssimSum += v.ssim;
        if (v.psnr < report.worstPsnr) {
            report.worstPsnr = v.psnr;
            report.worstView = v.name;
        }
    }
    const auto n = static_cast<double>(std::max<std::size_t>(report.views.size(), 1));
    report.psnr = psnrSum / n;
    report.ssim = ssimSum / n;
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace vpe::transfer
