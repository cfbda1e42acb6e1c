// SPDX-License-Identifier: MIT
// Show fidelity: every projector's frame rendered for a visitor, their combined light seen by
// that visitor, compared with the true material (see the header).
#include "vpe/transfer/show_fidelity.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "vpe/common/input_error.h"
#include "vpe/common/progress_bar.h"
#include "vpe/image/image_file.h"
#include "vpe/image/image_metrics.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/luminance.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"
#include "vpe/transfer/synthetic_truth.h"
#include "vpe/transfer/transfer_fidelity.h"

#include "show_inputs.h"

namespace vpe::transfer {

namespace {

using renderer::Vec3d;

// Pixels either side of a blend boundary whose steps are its reference: the surface's own
// variation there (texture, shading, foreshortening), which a seamless blend leaves alone.
constexpr int kSeamWindow = 4;

struct SeamSteps {
    double ratio = 0;
    std::size_t boundaryPairs = 0;
};

// A projector gives a visible part of the light where its share is above this: the set of
// projectors that do changes at a blend boundary. (Where the shares come from — smooth maps —
// and not from the reach itself, whose edge follows the mesh's facets at grazing incidence.)
constexpr float kVisibleShare = 0.01f;

// Per pixel, bit i set where projector i gives a visible part of the light.
renderer::ScalarImage<std::uint32_t> contributors(const renderer::SimulatedShowView& view) {
    renderer::ScalarImage<std::uint32_t> sets(view.coverage.width, view.coverage.height);
    for (std::size_t i = 0; i < view.shares.size(); ++i) {
        for (std::size_t p = 0; p < sets.values.size(); ++p) {
            sets.values[p] |= view.shares[i].values[p] > kVisibleShare ? 1u << i : 0u;
        }
    }
    return sets;
}

// The blend boundary's step against its neighbourhood's, on a scalar field over the viewer's
// pixels (`valid` where it means something). Pairs count when both pixels and their four
// neighbours are valid, on the object (no silhouette) and lit; a pair is on a boundary where
// the set of projectors that give a visible part of the light changes.
SeamSteps seamSteps(const std::vector<double>& field, const std::vector<std::uint8_t>& valid,
                    const renderer::SimulatedShowView& view) {
    const renderer::ScalarImage<std::uint32_t> sets = contributors(view);
    const int w = view.coverage.width, h = view.coverage.height;
    const auto index = [w](int x, int y) { return static_cast<std::size_t>(y) * w + x; };
    const auto inside = [&](int x, int y) {
        if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) {
            return false;
        }
        for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
            if (!valid[index(x + dx, y + dy)] || !view.coverage.at(x + dx, y + dy) ||
                view.litBy.at(x + dx, y + dy) == 0) {
                return false;
            }
        }
        return true;
    };
    const auto step = [&](int x0, int y0, int x1, int y1) {
        return std::fabs(field[index(x0, y0)] - field[index(x1, y1)]);
    };
    // Pass 1: the boundary pairs, and a map of the pixels near them.
    renderer::MaskImage near(w, h);
    std::vector<double> across, beside;
    SeamSteps result;
    for (int y = 1; y < h - 1; ++y) {
        for (int x = 1; x < w - 1; ++x) {
            for (const auto& [dx, dy] : {std::pair{1, 0}, {0, 1}}) {
                if (!inside(x, y) || !inside(x + dx, y + dy) ||
                    sets.at(x, y) == sets.at(x + dx, y + dy)) {
                    continue;
                }
                across.push_back(step(x, y, x + dx, y + dy));
                ++result.boundaryPairs;
                for (int ny = std::max(0, y - kSeamWindow); ny <= std::min(h - 1, y + kSeamWindow);
                     ++ny) {
                    for (int nx = std::max(0, x - kSeamWindow);
                         nx <= std::min(w - 1, x + kSeamWindow); ++nx) {
                        near.at(nx, ny) = 1;
                    }
                }
            }
        }
    }
    // Pass 2: the other pairs near a boundary.

    for (int y = 1; y < h - 1; ++y) {
        for (int x = 1; x < w - 1; ++x) {
            for (const auto& [dx, dy] : {std::pair{1, 0}, {0, 1}}) {
                if (!near.at(x, y) || !inside(x, y) || !inside(x + dx, y + dy) ||
                    sets.at(x, y) != sets.at(x + dx, y + dy)) {
                    continue;
                }
                beside.push_back(step(x, y, x + dx, y + dy));
            }
        }
    }
    // Medians: the relief's light error is sparse and heavy-tailed (single pixels where a
    // grazing projector pixel straddles a ridge), and a boundary crossing one would say
    // nothing about the blend.
    const auto median = [](std::vector<double>& values) {
        const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
        std::nth_element(values.begin(), middle, values.end());
        return *middle;
    };
    if (!across.empty() && !beside.empty()) {
        const double reference = median(beside);
        if (reference > 0) {
            result.ratio = median(across) / reference;
        }
    }
    return result;
}

// The light a visitor sees relative to what they should: the show's luminance over the
// material's rendered directly, where the material is at least 5% of its 99th percentile
// (darker, the ratio measures nothing anyone sees). The material's texture and shading cancel:
// what is left is the projection's own error, where a seam would show as a step.
std::vector<double> lightRatio(const renderer::SimulatedShowView& show,
                               const renderer::DirectView& direct,
                               std::vector<std::uint8_t>& valid) {
    const std::size_t n = show.coverage.values.size();
    std::vector<double> luminance(n, 0), ratio(n, 0);
    std::vector<double> sorted;
    for (std::size_t p = 0; p < n; ++p) {
        const float* d = &direct.radiance.values[3 * p];
        luminance[p] = proto::luminance709(static_cast<double>(d[0]), static_cast<double>(d[1]),
                                           static_cast<double>(d[2]));
        if (direct.coverage.values[p]) {
            sorted.push_back(luminance[p]);
        }
    }
    valid.assign(n, 0);
    if (sorted.empty()) {
        return ratio;
    }
    const auto at =
        sorted.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(sorted.size() - 1));
    std::nth_element(sorted.begin(), at, sorted.end());
    const double floor = 0.05 * *at;
    for (std::size_t p = 0; p < n; ++p) {
        if (!direct.coverage.values[p] || !(luminance[p] > floor)) {
            continue;
        }
        const float* s = &show.radiance.values[3 * p];
        ratio[p] = proto::luminance709(static_cast<double>(s[0]), static_cast<double>(s[1]),
                                       static_cast<double>(s[2])) /
                   luminance[p];
        valid[p] = 1;
    }
    return ratio;
}

// A picture's sRGB values averaged over the channels, everywhere valid.
std::vector<double> pictureField(const image::Rgb8Image& picture,
                                 std::vector<std::uint8_t>& valid) {
    const std::size_t n = static_cast<std::size_t>(picture.width) * picture.height;
    std::vector<double> field(n);
    for (std::size_t p = 0; p < n; ++p) {
        field[p] =
            (picture.values[3 * p] + picture.values[3 * p + 1] + picture.values[3 * p + 2]) / 3.0;
    }
    valid.assign(n, 1);
    return field;
}

// A picture of which projectors light each pixel: red none, then one colour per set.
std::vector<std::uint8_t> reachPicture(const renderer::SimulatedShowView& view) {
    static constexpr std::uint8_t kColours[8][3] = {{230, 40, 40},  {90, 90, 90},   {70, 130, 210},
                                                    {60, 190, 110}, {210, 170, 60}, {170, 90, 200},
                                                    {60, 190, 200}, {230, 230, 230}};
    std::vector<std::uint8_t> out(3 * view.coverage.values.size(), 0);
    for (std::size_t p = 0; p < view.coverage.values.size(); ++p) {
        if (view.coverage.values[p]) {
            const auto* colour = kColours[view.litBy.values[p] % 8];
            std::copy(colour, colour + 3, &out[3 * p]);
        }
    }
    return out;
}

}  // namespace

ShowCheckReport checkShow(const ShowCheckOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (options.views < 1) {
        throw common::InputError("--views: expected at least 1");
    }
    const detail::ShowInputs inputs(options.capture, options.bundles);
    const SyntheticTruth& truth = inputs.truth();
    const auto& scenes = inputs.scenes();
    const auto at = [&](double azimuth, double elevation) { return inputs.at(azimuth, elevation); };
    const proto::Vec3d centre = inputs.centre();
    if (!options.out.empty()) {
        std::filesystem::create_directories(options.out);
    }

    ShowCheckReport report;
    std::size_t seen = 0, lit = 0;
    common::ProgressBar progress("show", static_cast<std::size_t>(options.views));
    for (int k = 0; k < options.views; ++k) {
        ShowViewCheck check;
        check.azimuthDegrees = 360.0 * k / options.views;
        const proto::Vec3d viewer = at(check.azimuthDegrees, options.elevationDegrees);
        renderer::VirtualLight light;
        light.position =
            at(check.azimuthDegrees + options.lightAzimuthDegrees, options.lightElevationDegrees);
        renderer::RenderOptions renderOptions;
        renderOptions.threads = options.threads;
        std::vector<renderer::RenderScene> renderScenes;
        std::vector<renderer::RgbImage> frames;
        for (const auto& scene : scenes) {
            renderScenes.push_back(scene->scene(light, viewer));
            renderOptions.gain = static_cast<double>(scene->bundle().settings().gain);
            frames.push_back(detail::quantized(
                renderer::renderProjectorFrame(renderScenes.back(), renderOptions).level));
        }
        std::vector<const renderer::RenderScene*> scenePointers;
        std::vector<const renderer::RgbImage*> patterns;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            scenePointers.push_back(&renderScenes[i]);
            patterns.push_back(&frames[i]);
        }
        const proto::PinholeCamera camera = proto::cameraLookingAt(
            options.viewWidth, options.viewHeight, options.fovDegrees, viewer, centre);
        const renderer::SimulatedShowView show =
            renderer::simulateShowView(scenePointers, patterns, camera, renderOptions);
        const renderer::RgbImage truthImage =
            renderTruthView(renderScenes.front(), truth, camera, options.threads);
        const double exposure = truthExposure(truthImage, show.coverage);
        const image::Rgb8Image a =
            image::toSrgb8(truthImage.values, camera.width, camera.height, exposure);
        const image::Rgb8Image b =
            image::toSrgb8(show.radiance.values, camera.width, camera.height, exposure);
        std::vector<std::uint8_t> compared(show.coverage.values.size(), 0);
        for (std::size_t p = 0; p < compared.size(); ++p) {
            if (!show.coverage.values[p]) {
                continue;
            }
            ++check.seenPixels;
            if (show.litBy.values[p] == 0) {
                continue;
            }
            ++check.litPixels;
            for (std::size_t c = 0; c < 3; ++c) {
                compared[p] = compared[p] || a.values[3 * p + c] > 0 || b.values[3 * p + c] > 0;
            }
        }
        check.psnr = image::psnr(a, b, compared);
        const renderer::DirectView direct =
            renderer::renderDirectView(renderScenes.front(), camera, renderOptions);
        std::vector<std::uint8_t> valid;
        const std::vector<double> ratio = lightRatio(show, direct, valid);
        const SeamSteps steps = seamSteps(ratio, valid, show);
        check.seamStepRatio = steps.ratio;
        check.boundaryPairs = steps.boundaryPairs;
        check.pictureSeamStepRatio = seamSteps(pictureField(b, valid), valid, show).ratio;
        check.truthSeamStepRatio = seamSteps(pictureField(a, valid), valid, show).ratio;
        seen += check.seenPixels;
        lit += check.litPixels;
        if (!options.out.empty()) {
            const std::string base =
                (options.out / ("view" + std::to_string(static_cast<int>(check.azimuthDegrees))))
                    .string();
            image::writeImage8(base + "-truth.png", a.width, a.height, 3, a.values);
            image::writeImage8(base + "-show.png", b.width, b.height, 3, b.values);
            image::writeImage8(base + "-reach.png", a.width, a.height, 3, reachPicture(show));
            // The light relative to the material: mid grey 1, black 0.8 or less, white 1.2 or
            // more; red where it is not measured (too dark, or unlit).
            std::vector<std::uint8_t> relative(3 * ratio.size(), 0);
            for (std::size_t p = 0; p < ratio.size(); ++p) {
                if (!show.coverage.values[p]) {
                    continue;
                }
                if (!valid[p]) {
                    relative[3 * p] = 160;
                    continue;
                }
                const auto v = static_cast<std::uint8_t>(
                    std::lround(255 * std::clamp((ratio[p] - 0.8) / 0.4, 0.0, 1.0)));
                relative[3 * p] = relative[3 * p + 1] = relative[3 * p + 2] = v;
            }
            // The blend boundaries the seam is measured across, in blue.
            const renderer::ScalarImage<std::uint32_t> sets = contributors(show);
            for (int y = 0; y + 1 < a.height; ++y) {
                for (int x = 0; x + 1 < a.width; ++x) {
                    if (show.coverage.at(x, y) && (sets.at(x, y) != sets.at(x + 1, y) ||
                                                   sets.at(x, y) != sets.at(x, y + 1))) {
                        std::uint8_t* rgb =
                            &relative[3 * (static_cast<std::size_t>(y) * a.width + x)];
                        rgb[0] = 40;
                        rgb[1] = 90;
                        rgb[2] = 255;
                    }
                }
            }
            image::writeImage8(base + "-light.png", a.width, a.height, 3, relative);
        }
        report.views.push_back(check);
        progress.advance();
    }
    progress.finish();
    double sum = 0;
    report.worstPsnr = 1e30;
    for (const ShowViewCheck& v : report.views) {
        sum += v.psnr;
        report.worstPsnr = std::min(report.worstPsnr, v.psnr);
        if (v.boundaryPairs > 0) {
            report.worstSeamStepRatio = std::max(report.worstSeamStepRatio, v.seamStepRatio);
        }
    }
    report.meanPsnr = sum / static_cast<double>(report.views.size());
    report.litShare = seen > 0 ? static_cast<double>(lit) / static_cast<double>(seen) : 0.0;
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace vpe::transfer
