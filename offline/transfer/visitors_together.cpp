// SPDX-License-Identifier: MIT
// Visitors together: one light, each projector's frame drawn once, every visitor scored from
// where they stand (see the header).
#include "vpe/transfer/visitors_together.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "vpe/common/input_error.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/quantile.h"
#include "vpe/image/image_file.h"
#include "vpe/image/image_metrics.h"
#include "vpe/proto/luminance.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"
#include "vpe/transfer/transfer_fidelity.h"

#include "show_inputs.h"

namespace vpe::transfer {

namespace {

using renderer::Vec3d;

struct Visitor {
    std::string where;
    double azimuth = 0, elevation = 0;
};

std::vector<Visitor> standingVisitors(const TogetherOptions& options) {
    std::vector<Visitor> visitors;
    for (int k = 0; k < options.eyeVisitors; ++k) {
        visitors.push_back({"eye", 360.0 * k / options.eyeVisitors, options.show.elevationDegrees});
    }
    // Children between the adults, on opposite sides.
    for (int k = 0; k < options.childVisitors; ++k) {
        const double between = options.eyeVisitors > 0 ? 180.0 / options.eyeVisitors : 0;
        visitors.push_back(
            {"child", 360.0 * k / options.childVisitors + between, options.childElevationDegrees});
    }
    if (options.visitorAbove) {
        visitors.push_back({"above", 0, options.aboveElevationDegrees});
    }
    return visitors;
}

// The azimuth (degrees, directionAt's) of a point seen from the object's middle.
double azimuthOf(const Vec3d& point, const Vec3d& centre) {
    return std::atan2(point.x - centre.x, point.z - centre.z) * 180.0 / std::numbers::pi;
}

std::vector<double> luminances(const renderer::RgbImage& image) {
    std::vector<double> out(image.values.size() / 3);
    for (std::size_t p = 0; p < out.size(); ++p) {
        out[p] = proto::luminance709(image.values[3 * p], image.values[3 * p + 1],
                                     image.values[3 * p + 2]);
    }
    return out;
}

// The pixels among `compared` in the top `share` of `value` (and above 0).
std::vector<std::size_t> topPixels(const std::vector<double>& value,
                                   const std::vector<std::uint8_t>& compared, double share) {
    std::vector<double> values;
    for (std::size_t p = 0; p < value.size(); ++p) {
        if (compared[p]) {
            values.push_back(value[p]);
        }
    }
    std::vector<std::size_t> top;
    if (values.empty()) {
        return top;
    }
    const double threshold = std::max(common::quantile(values, 1.0 - share), 1e-12);
    for (std::size_t p = 0; p < value.size(); ++p) {
        if (compared[p] && value[p] >= threshold) {
            top.push_back(p);
        }
    }
    return top;
}

// Of the true highlights, the share with a show highlight within `radius` pixels.
double highlightsSeen(const std::vector<std::size_t>& truth, const std::vector<std::size_t>& show,
                      int width, double radius) {
    if (truth.empty()) {
        return 1.0;
    }
    std::size_t seen = 0;
    for (const std::size_t t : truth) {
        const double tx = double(t % width), ty = double(t / width);
        for (const std::size_t s : show) {
            const double dx = double(s % width) - tx, dy = double(s / width) - ty;
            if (dx * dx + dy * dy <= radius * radius) {
                ++seen;
                break;
            }
        }
    }
    return double(seen) / double(truth.size());
}

}  // namespace

std::string viewerModelName(ViewerModel model) {
    switch (model) {
        case ViewerModel::kBundle:
            return "bundle";
        case ViewerModel::kProjectorSide:
            return "projector-side";
        case ViewerModel::kZone:
            return "zone";
        case ViewerModel::kTracked:
            return "tracked";
    }
    return "bundle";
}

ViewerModel parseViewerModel(const std::string& word, const std::string& what) {
    for (const ViewerModel model : {ViewerModel::kBundle, ViewerModel::kProjectorSide,
                                    ViewerModel::kZone, ViewerModel::kTracked}) {
        if (word == viewerModelName(model)) {
            return model;
        }
    }
    throw common::InputError(what + ": '" + word +
                             "' is not a viewer model (bundle, projector-side, zone, tracked)");
}

TogetherReport checkVisitorsTogether(const TogetherOptions& options, ViewerModel model) {
    const auto start = std::chrono::steady_clock::now();
    const ShowCheckOptions& show = options.show;
    const std::vector<Visitor> visitors = standingVisitors(options);
    if (visitors.empty()) {
        throw common::InputError("--together: no visitors");
    }
    const detail::ShowInputs inputs(show.capture, show.bundles);
    const auto& scenes = inputs.scenes();
    renderer::VirtualLight light;
    light.position = inputs.at(show.lightAzimuthDegrees, show.lightElevationDegrees);
    std::vector<Vec3d> eyes;
    for (const Visitor& v : visitors) {
        eyes.push_back(inputs.at(v.azimuth, v.elevation));
    }
    renderer::RenderOptions renderOptions;
    renderOptions.threads = show.threads;

    // Every projector's scene and frame, for one eye (kTracked) or for the model's.
    std::vector<renderer::RenderScene> renderScenes;
    std::vector<renderer::RgbImage> frames;
    const auto drawFrames = [&](const Vec3d* trackedEye) {
        renderScenes.clear();
        frames.clear();
        for (const auto& scene : scenes) {
            // As the device draws the bundle (its viewer, and its zone where it has one), or for
            // one eye, or for the visitors themselves as the zone.
            renderer::RenderScene rs = scene->scene(light);
            if (trackedEye != nullptr) {
                rs = scene->scene(light, *trackedEye);
            } else if (model == ViewerModel::kProjectorSide) {
                rs = scene->scene(
                    light, inputs.at(azimuthOf(rs.projector.camera.center(), inputs.centre()),
                                     show.elevationDegrees));
            } else if (model == ViewerModel::kZone) {
                rs.viewingZone.clear();
                for (const Vec3d& eye : eyes) {
                    rs.viewingZone.push_back({static_cast<float>(eye.x), static_cast<float>(eye.y),
                                              static_cast<float>(eye.z)});
                }
            }
            renderOptions.gain = static_cast<double>(scene->bundle().settings().gain);
            frames.push_back(
                detail::quantized(renderer::renderProjectorFrame(rs, renderOptions).level));
            renderScenes.push_back(std::move(rs));
        }
    };
    if (model != ViewerModel::kTracked) {
        drawFrames(nullptr);
    }
    if (!show.out.empty()) {
        std::filesystem::create_directories(show.out);
    }

    // What each visitor sees, and the truth there.
    struct Seen {
        renderer::SimulatedShowView view;
        renderer::RgbImage truth, truthViewDependent;
        proto::PinholeCamera camera;
    };
    std::vector<Seen> seen;
    common::ProgressBar progress("visitors " + viewerModelName(model), visitors.size());
    for (std::size_t k = 0; k < visitors.size(); ++k) {
        if (model == ViewerModel::kTracked) {
            drawFrames(&eyes[k]);
        }
        std::vector<const renderer::RenderScene*> scenePointers;
        std::vector<const renderer::RgbImage*> patterns;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            scenePointers.push_back(&renderScenes[i]);
            patterns.push_back(&frames[i]);
        }
        Seen one;
        one.camera = proto::cameraLookingAt(show.viewWidth, show.viewHeight, show.fovDegrees,
                                            eyes[k], inputs.centre());
        one.view = renderer::simulateShowView(scenePointers, patterns, one.camera, renderOptions);
        one.truth = renderTruthView(renderScenes.front(), inputs.truth(), one.camera, show.threads,
                                    &one.truthViewDependent);
        seen.push_back(std::move(one));
        progress.advance();
    }
    progress.finish();
    // One exposure for the room, the brightest view's: the visitors stand in one gallery, and a
    // view of the object's unlit side is dark for them, not exposed up to its projectors' black.
    double exposure = 1e300;
    for (const Seen& one : seen) {
        exposure = std::min(exposure, truthExposure(one.truth, one.view.coverage));
    }

    TogetherReport report;
    report.model = model;
    const double radius = options.highlightDegrees / (show.fovDegrees / show.viewHeight);
    for (std::size_t k = 0; k < visitors.size(); ++k) {
        const renderer::SimulatedShowView& view = seen[k].view;
        const renderer::RgbImage& truthImage = seen[k].truth;
        const renderer::RgbImage& truthViewDependent = seen[k].truthViewDependent;
        const proto::PinholeCamera& camera = seen[k].camera;
        VisitorCheck check;
        check.where = visitors[k].where;
        check.azimuthDegrees = visitors[k].azimuth;
        check.elevationDegrees = visitors[k].elevation;
        const image::Rgb8Image a =
            image::toSrgb8(truthImage.values, camera.width, camera.height, exposure);
        const image::Rgb8Image b =
            image::toSrgb8(view.radiance.values, camera.width, camera.height, exposure);
        std::vector<std::uint8_t> compared(view.coverage.values.size(), 0);
        for (std::size_t p = 0; p < compared.size(); ++p) {
            if (!view.coverage.values[p]) {
                continue;
            }
            ++check.seenPixels;
            if (view.litBy.values[p] == 0) {
                continue;
            }
            ++check.litPixels;
            // Every pixel of the object a projector reaches: the unlit side a visitor sees dark
            // and the show leaves dark is seen right.
            compared[p] = 1;
        }
        check.psnr = image::psnr(a, b, compared);
        // The show's view-dependent light: what it sends less the truth's part that is the same
        // from anywhere (a show that gets the diffuse part right leaves its highlights).
        const std::vector<double> truthAll = luminances(truthImage),
                                  truthHighlight = luminances(truthViewDependent),
                                  shown = luminances(view.radiance);
        std::vector<double> shownHighlight(shown.size());
        for (std::size_t p = 0; p < shown.size(); ++p) {
            shownHighlight[p] = shown[p] - (truthAll[p] - truthHighlight[p]);
        }
        check.highlightShare = highlightsSeen(
            topPixels(truthHighlight, compared, options.highlightShare),
            topPixels(shownHighlight, compared, options.highlightShare), camera.width, radius);
        if (!show.out.empty()) {
            // truth | show | difference ×4, one row per visitor.
            const int w = camera.width, h = camera.height;
            std::vector<std::uint8_t> row(static_cast<std::size_t>(3 * w) * 3 * h, 0);
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    const std::size_t p = static_cast<std::size_t>(y) * w + x;
                    for (std::size_t c = 0; c < 3; ++c) {
                        const int ta = a.values[3 * p + c], tb = b.values[3 * p + c];
                        std::uint8_t* out = &row[3 * (static_cast<std::size_t>(y) * 3 * w + x)];
                        out[c] = static_cast<std::uint8_t>(ta);
                        out[3 * w + c] = static_cast<std::uint8_t>(tb);
                        out[6 * w + c] =
                            static_cast<std::uint8_t>(std::min(255, 4 * std::abs(ta - tb)));
                    }
                }
            }
            const std::string name = viewerModelName(model) + "-" + check.where + "-" +
                                     std::to_string(static_cast<int>(check.azimuthDegrees)) +
                                     ".png";
            image::writeImage8((show.out / name).string(), 3 * w, h, 3, row);
        }
        report.visitors.push_back(check);
    }

    double psnrSum = 0, highlightSum = 0;
    int standing = 0;
    report.worstPsnr = report.worstHighlightShare = 1e30;
    for (const VisitorCheck& v : report.visitors) {
        if (v.where == "above") {
            continue;
        }
        ++standing;
        psnrSum += v.psnr;
        highlightSum += v.highlightShare;
        report.worstPsnr = std::min(report.worstPsnr, v.psnr);
        report.worstHighlightShare = std::min(report.worstHighlightShare, v.highlightShare);
    }
    if (standing > 0) {
        report.meanPsnr = psnrSum / standing;
        report.meanHighlightShare = highlightSum / standing;
    } else {
        report.worstPsnr = report.worstHighlightShare = 0;
    }
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace vpe::transfer
