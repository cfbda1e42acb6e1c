// SPDX-License-Identifier: MIT
// measureRadiometry: the flat fields, sampled where each projector pixel's light lands in the
// camera, fitted to C = D + F · X · g (see the header).
#include "vpe/radiometry/projector_radiometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/quantile.h"
#include "vpe/image/image_file.h"
#include "vpe/radiometry/camera_response.h"
#include "vpe/radiometry/floor_split.h"

namespace vpe::radiometry {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Where projector pixel `index` falls in the camera.
struct Sample {
    std::uint32_t index = 0;
    float u = 0, v = 0;
    float geometry = 0;  // S of the projector's light there
};

// Bilinear, the camera's pixel centres at integer coordinates.
void sampleAt(const image::FloatImage& image, float u, float v, float* out) {
    const int x0 = std::clamp(static_cast<int>(std::floor(u)), 0, image.width - 2);
    const int y0 = std::clamp(static_cast<int>(std::floor(v)), 0, image.height - 2);
    const float fx = std::clamp(u - static_cast<float>(x0), 0.0f, 1.0f);
    const float fy = std::clamp(v - static_cast<float>(y0), 0.0f, 1.0f);
    for (int c = 0; c < 3; ++c) {
        const float a = image.at(x0, y0, c), b = image.at(x0 + 1, y0, c);
        const float d = image.at(x0, y0 + 1, c), e = image.at(x0 + 1, y0 + 1, c);
        const float top = a + fx * (b - a), bottom = d + fx * (e - d);
        out[c] = top + fy * (bottom - top);
    }
}

double robustSigma(const std::vector<double>& values, double centre) {
    std::vector<double> deviations;
    deviations.reserve(values.size());
    for (const double v : values) {
        deviations.push_back(std::abs(v - centre));
    }
    return 1.4826 * common::quantile(std::move(deviations), 0.5);
}

// One flat field read, its size checked and its codes made linear.
image::FloatImage readField(const std::filesystem::path& path, const proto::RadiometryManifest& m,
                            const CameraLinearization& linearization) {
    image::FloatImage image = image::readImage(path);
    if (image.width != m.camera.width || image.height != m.camera.height || image.channels != 3) {
        throw common::InputError(
            path, "the image is " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + "x" + std::to_string(image.channels) +
                      ", the capture's camera " + std::to_string(m.camera.width) + "x" +
                      std::to_string(m.camera.height) + "x3");
    }
    if (!linearization.isLinear()) {
        const int top = linearization.maxValue();
        for (std::size_t i = 0; i < image.pixels.size(); ++i) {
            const int code =
                std::clamp(static_cast<int>(std::lround(image.pixels[i] * top)), 0, top);
            image.pixels[i] =
                static_cast<float>(linearization.linear(static_cast<int>(i % 3), code));
        }
    }
    return image;
}

// The pixels whose floor the split reads, per channel: well lit (`strong`), their light at most
// 60° from the normal — the scan's normals are good to about a degree, which at grazing light is
// several per cent of S, and the split leans on S — and with every pixel of the scan's normal
// window (7 × 7) measured, not at the outline, whose normals are fitted to half a window. Blocks
// of 1/20 of the projector's width are the bootstrap's unit: the model's misfit (interreflection,
// the normals' errors) is smooth over the object, and smaller blocks understate the errors.
std::array<std::vector<FloorSample>, 3> floorSamples(const std::vector<Sample>& samples,
                                                     const std::vector<std::uint8_t>& strong,
                                                     const scan::ProjectorSurface& surface,
                                                     const proto::PinholeCamera& projector,
                                                     const std::vector<float>& floor,
                                                     const std::vector<float>& irradiance) {
    constexpr double kMinCosine = 0.5;
    constexpr int kWindow = 3;  // the scan's normal radius (ProjectorSurfaceOptions)
    const int width = surface.width, height = surface.height;
    std::vector<std::uint8_t> known(static_cast<std::size_t>(width) * height, 0);
    for (const Sample& sample : samples) {
        known[sample.index] = 1;
    }
    const auto wholeWindow = [&](int x, int y) {
        for (int j = y - kWindow; j <= y + kWindow; ++j) {
            for (int i = x - kWindow; i <= x + kWindow; ++i) {
                if (i < 0 || j < 0 || i >= width || j >= height ||
                    !known[static_cast<std::size_t>(j) * width + i]) {
                    return false;
                }
            }
        }
        return true;
    };
    const std::uint32_t side = static_cast<std::uint32_t>(std::max(8, width / 20));
    const std::uint32_t across = (static_cast<std::uint32_t>(width) + side - 1) / side;
    const proto::Vec3d centre = projector.center();
    std::array<std::vector<FloorSample>, 3> channels;
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const std::uint32_t p = samples[s].index;
        const int x = static_cast<int>(p % static_cast<std::uint32_t>(width));
        const int y = static_cast<int>(p / static_cast<std::uint32_t>(width));
        const float* q = &surface.position[3 * p];
        const double dx = centre.x - double(q[0]), dy = centre.y - double(q[1]),
                     dz = centre.z - double(q[2]);
        const double cosine = double(samples[s].geometry) * (dx * dx + dy * dy + dz * dz);
        if (!strong[s] || cosine < kMinCosine || !wholeWindow(x, y)) {
            continue;
        }
        const std::uint32_t block =
            (static_cast<std::uint32_t>(y) / side) * across + static_cast<std::uint32_t>(x) / side;
        for (std::size_t k = 0; k < 3; ++k) {
            channels[k].push_back(
                {floor[3 * p + k], irradiance[3 * p + k], samples[s].geometry, block});
        }
    }
    return channels;
}

}  // namespace

double projectorGeometry(const proto::PinholeCamera& projector, const float* position,
                         const float* normal) {
    if (std::isnan(position[0]) || std::isnan(normal[0])) {
        return 0;
    }
    const proto::Vec3d centre = projector.center();
    const double dx = centre.x - double(position[0]), dy = centre.y - double(position[1]),
                 dz = centre.z - double(position[2]);
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double cosine =
        (dx * double(normal[0]) + dy * double(normal[1]) + dz * double(normal[2])) / std::sqrt(d2);
    return cosine > 0 ? cosine / d2 : 0.0;
}

ProjectorRadiometry measureRadiometry(const std::filesystem::path& capture,
                                      const scan::ProjectorSurface& surface,
                                      const proto::PinholeCamera& camera,
                                      const proto::PinholeCamera& projector,
                                      const RadiometryOptions& options,
                                      common::ProgressBar* progress) {
    const auto start = std::chrono::steady_clock::now();
    const proto::RadiometryManifest m = proto::readRadiometryManifest(capture);
    const std::filesystem::path folder = proto::scanFolderOf(capture);
    const std::vector<proto::FlatField> fields = proto::radiometrySequence(m.fields);
    const auto fieldPath = [&](std::size_t i) { return folder / m.images[i].file; };
    if (m.fields.width != surface.width || m.fields.height != surface.height) {
        throw common::InputError(folder / proto::kRadiometryManifestName,
                                 "flat fields for a " + std::to_string(m.fields.width) + "x" +
                                     std::to_string(m.fields.height) +
                                     " projector, the scan's is " + std::to_string(surface.width) +
                                     "x" + std::to_string(surface.height));
    }
    if (m.camera.width != camera.width || m.camera.height != camera.height) {
        throw common::InputError(
            folder / proto::kRadiometryManifestName,
            "a " + std::to_string(m.camera.width) + "x" + std::to_string(m.camera.height) +
                " capture, the scan's camera is " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height) + ": capture both with the same camera mode");
    }
    for (std::size_t i = 0; i < m.images.size(); ++i) {
        if (!std::filesystem::exists(fieldPath(i))) {
            throw common::InputError(
                fieldPath(i),
                "missing: the flat field '" + m.images[i].pattern + "' the manifest lists");
        }
    }

    // The camera's response: linear raw data, or measured from the bracketed ramp.
    CameraLinearization linearization = CameraLinearization::identity(1, 3);
    if (m.camera.response == proto::CameraResponseKind::kUnknown) {
        std::vector<BracketedImage> bracket;
        for (std::size_t i = 0; i < fields.size(); ++i) {
            if (fields[i].kind != proto::FlatFieldKind::kRamp) {
                continue;
            }
            const image::FloatImage ramp = image::readImage(fieldPath(i));
            BracketedImage image;
            image.width = ramp.width;
            image.height = ramp.height;
            image.channels = ramp.channels;
            image.maxValue = 255;
            image.exposure = fields[i].exposureScale();
            image.samples.reserve(ramp.pixels.size());
            for (const float v : ramp.pixels) {
                image.samples.push_back(
                    static_cast<std::uint16_t>(std::clamp(std::lround(v * 255.0f), 0L, 255L)));
            }
            bracket.push_back(std::move(image));
        }
        linearization = fitCameraResponse(bracket);
    }

    // Where every measured projector pixel's light lands in the camera.
    std::vector<Sample> samples;
    for (std::size_t p = 0; p < static_cast<std::size_t>(surface.width) * surface.height; ++p) {
        const float* position = &surface.position[3 * p];
        if (std::isnan(position[0])) {
            continue;
        }
        const auto pixel = proto::projectToPixel(camera, {position[0], position[1], position[2]});
        if (!pixel || pixel->x < 0.5 || pixel->y < 0.5 || pixel->x > camera.width - 1.5 ||
            pixel->y > camera.height - 1.5) {
            continue;
        }
        const double geometry = projectorGeometry(projector, position, &surface.normal[3 * p]);
        if (geometry <= 0) {
            continue;
        }
        samples.push_back({static_cast<std::uint32_t>(p), static_cast<float>(pixel->x),
                           static_cast<float>(pixel->y), static_cast<float>(geometry)});
    }
    if (samples.empty()) {
        throw common::InputError(folder, "no projector pixel of the scan falls inside the camera");
    }
    const std::size_t n = samples.size();
    const unsigned threads = common::resolveThreadCount(options.threads);

    // Every field sampled at every pixel: values[field][sample][channel].
    std::vector<std::vector<float>> values(fields.size());
    std::vector<float> whiteRaw;
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].kind == proto::FlatFieldKind::kRamp) {
            if (progress) {
                progress->advance();
            }
            continue;
        }
        const image::FloatImage image = readField(fieldPath(i), m, linearization);
        values[i].resize(3 * n);
        common::parallelFor(n, 4096, threads, [&](std::size_t begin, std::size_t end) {
            for (std::size_t s = begin; s < end; ++s) {
                sampleAt(image, samples[s].u, samples[s].v, &values[i][3 * s]);
            }
        });
        if (fields[i].kind == proto::FlatFieldKind::kWhite) {
            // Saturation is a property of the codes: the nearest camera pixel, not the mean.
            whiteRaw.resize(n);
            for (std::size_t s = 0; s < n; ++s) {
                const int x = static_cast<int>(std::lround(samples[s].u));
                const int y = static_cast<int>(std::lround(samples[s].v));
                whiteRaw[s] = std::max({image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)});
            }
        }
        if (progress) {
            progress->advance();
        }
    }
    const std::size_t black = 0, white = 1;

    ProjectorRadiometry r;
    r.width = surface.width;
    r.height = surface.height;
    r.cameraLinear = linearization.isLinear();
    r.exposureUs = m.camera.exposureUs;

    // Is the exposure right? White must not clip; white above black must be well above noise.
    const float top = static_cast<float>(linearization.linear(0, linearization.maxValue()));
    std::size_t saturated = 0;
    for (const float v : whiteRaw) {
        saturated += v >= 0.999f * top ? 1 : 0;
    }
    r.whiteSaturatedShare = static_cast<double>(saturated) / static_cast<double>(n);
    if (r.whiteSaturatedShare > options.maxSaturatedShare) {
        throw common::InputError(
            fieldPath(white),
            std::to_string(static_cast<int>(std::lround(1000 * r.whiteSaturatedShare)) / 10.0)
                    .substr(0, 4) +
                "% of the object saturates the camera: shorten the exposure (or "
                "lower the gain) until white stays below full scale");
    }
    {
        std::vector<double> signal(n);
        for (std::size_t s = 0; s < n; ++s) {
            double above = 0;
            for (int c = 0; c < 3; ++c) {
                above += double(values[white][3 * s + c]) - double(values[black][3 * s + c]);
            }
            signal[s] = above / 3;
        }
        r.whiteSignal = common::quantile(std::move(signal), 0.5) / double(top);
    }
    if (r.whiteSignal < options.minWhiteSignal) {
        throw common::InputError(
            fieldPath(black),
            "the floor is lost in the camera's noise: white rises only " +
                std::to_string(static_cast<int>(std::lround(100 * r.whiteSignal))) +
                "% of the range above black on the object (at least " +
                std::to_string(static_cast<int>(std::lround(100 * options.minWhiteSignal))) +
                "% wanted): lengthen the exposure (or raise the gain)");
    }

    // The full-level primaries: per pixel, column c of diag(F)·X is primary c above black.
    std::array<std::size_t, 3> full{};
    std::vector<std::array<std::size_t, 2>> ladder;  // (field, channel) of every primary level
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].kind == proto::FlatFieldKind::kPrimary) {
            ladder.push_back({i, static_cast<std::size_t>(fields[i].channel)});
            if (fields[i].code == 255) {
                full[static_cast<std::size_t>(fields[i].channel)] = i;
            }
        }
    }
    const auto column = [&](std::size_t s, std::size_t k, std::size_t c) {
        return double(values[full[c]][3 * s + k]) - double(values[black][3 * s + k]);
    };
    // Pixels lit well enough to read ratios from: a quarter of the median white signal.
    std::vector<std::uint8_t> strong(n, 0);
    for (std::size_t s = 0; s < n; ++s) {
        bool ok = true;
        for (std::size_t k = 0; k < 3; ++k) {
            ok = ok && column(s, k, k) > 0.25 * r.whiteSignal * double(top);
        }
        strong[s] = ok ? 1 : 0;
    }

    // X: the median of the per-pixel ratios; their spread against the noise neighbours show.
    for (std::size_t k = 0; k < 3; ++k) {
        for (std::size_t c = 0; c < 3; ++c) {
            if (k == c) {
                continue;
            }
            std::vector<double> ratios, differences;
            double previous = std::numeric_limits<double>::quiet_NaN();
            std::uint32_t previousIndex = 0;
            for (std::size_t s = 0; s < n; ++s) {
                if (!strong[s]) {
                    continue;
                }
                const double ratio = column(s, k, c) / column(s, k, k);
                ratios.push_back(ratio);
                if (samples[s].index == previousIndex + 1 && !std::isnan(previous)) {
                    differences.push_back(ratio - previous);
                }
                previous = ratio;
                previousIndex = samples[s].index;
            }
            const double median = common::quantile(ratios, 0.5);
            r.mixing[3 * k + c] = median;
            r.mixingSpread[3 * k + c] = robustSigma(ratios, median);
            r.mixingNoise[3 * k + c] = robustSigma(differences, 0.0) / std::sqrt(2.0);
        }
    }

    // g_c at each level: the median over the object of primary c's own channel, above black,
    // as a share of the full level's.
    std::array<std::vector<std::pair<double, double>>, 3> curve;
    for (const auto& [field, channel] : ladder) {
        std::vector<double> ratios;
        for (std::size_t s = 0; s < n; ++s) {
            if (strong[s]) {
                ratios.push_back((double(values[field][3 * s + channel]) -
                                  double(values[black][3 * s + channel])) /
                                 column(s, channel, channel));
            }
        }
        curve[channel].emplace_back(fields[field].code / 255.0, common::quantile(ratios, 0.5));
    }
    r.levels.push_back(0);
    for (const auto& [level, g] : curve[0]) {
        r.levels.push_back(level);
    }
    for (std::size_t c = 0; c < 3; ++c) {
        r.response[c].push_back(0);
        double running = 0;
        for (const auto& [level, g] : curve[c]) {
            running = std::clamp(std::max(running, g), 0.0, 1.0);  // non-decreasing, as measured
            r.response[c].push_back(running);
        }
        r.response[c].back() = 1;  // the full level is the reference
    }

    // Per pixel, D and F together by least squares over every flat field: C = D + F · a with
    // a = Σ_c X_kc g_c(level_c) known now.
    std::vector<std::array<double, 3>> predicted(fields.size());
    const auto gAt = [&](std::size_t c, int code) {
        for (std::size_t l = 0; l < r.levels.size(); ++l) {
            if (std::abs(r.levels[l] * 255.0 - code) < 0.5) {
                return r.response[c][l];
            }
        }
        return code == 0 ? 0.0 : 1.0;
    };
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].kind == proto::FlatFieldKind::kRamp) {
            continue;
        }
        const std::array<std::uint8_t, 3> codes = fields[i].codes(0, 1);
        for (std::size_t k = 0; k < 3; ++k) {
            double a = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                a += r.mixing[3 * k + c] * gAt(c, codes[c]);
            }
            predicted[i][k] = a;
        }
    }
    const std::size_t pixels = static_cast<std::size_t>(r.width) * r.height;
    r.irradiance.assign(3 * pixels, kNaN);
    r.floor.assign(3 * pixels, kNaN);
    common::parallelFor(n, 4096, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t s = begin; s < end; ++s) {
            for (std::size_t k = 0; k < 3; ++k) {
                double sa = 0, saa = 0, sy = 0, say = 0, count = 0;
                for (std::size_t i = 0; i < fields.size(); ++i) {
                    if (values[i].empty()) {
                        continue;
                    }
                    const double a = predicted[i][k], y = double(values[i][3 * s + k]);
                    sa += a;
                    saa += a * a;
                    sy += y;
                    say += a * y;
                    count += 1;
                }
                const double determinant = count * saa - sa * sa;
                const double f = (count * say - sa * sy) / determinant;
                const double d = (sy - f * sa) / count;
                r.irradiance[3 * samples[s].index + k] = static_cast<float>(f);
                r.floor[3 * samples[s].index + k] = static_cast<float>(d);
            }
        }
    });
    r.measured = n;

    // The floor split into the camera's black, the projector's and the room's light, with their
    // errors (floor_split.h).
    FloorSplitOptions split;
    split.cameraBlack = options.cameraBlack;
    r.floorSplit =
        splitFloor(floorSamples(samples, strong, surface, projector, r.floor, r.irradiance), split);
    r.fitSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

}  // namespace vpe::radiometry
