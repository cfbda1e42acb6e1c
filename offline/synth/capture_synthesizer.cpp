// SPDX-License-Identifier: MIT
// Rendering and writing the synthetic capture.
#include "vpe/synth/capture_synthesizer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/random_bits.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/srgb.h"
#include "vpe/synth/light_rigs.h"
#include "vpe/synth/pottery_scene.h"

namespace vpe::synth {

namespace {

constexpr double kFullWell = 5000.0;  // electrons at full scale: shot noise σ = √(y / 5000)
constexpr double kReadNoise = 0.002;  // of full scale

// The Fourier-family truth: coefficients that follow the material (diffuse albedo, a lobe
// that narrows with gloss), so the pattern stays visible in a Fourier capture too.
void fourierCoefficients(const MicrofacetMaterial& material, int harmonics, int channel,
                         double* coefficients) {
    const double albedo[3] = {material.albedo.x, material.albedo.y, material.albedo.z};
    const double gloss = 0.3 * std::clamp(1.0 - material.roughness, 0.0, 1.0);
    coefficients[proto::kLambertIndex] = albedo[channel];
    coefficients[proto::kConstantIndex] = 0.01;
    for (int m = 1; m <= harmonics; ++m) {
        coefficients[proto::cosineIndex(m)] = gloss * std::exp(-0.35 * m);
        coefficients[proto::sineIndex(m)] = 0.1 * gloss * std::exp(-0.5 * m) * (channel + 1) / 3.0;
    }
}

double gaussian(std::uint64_t key) {
    const double u1 = std::max(common::uniformFromBits(common::mixBits(key)), 1e-300);
    const double u2 = common::uniformFromBits(common::mixBits(key ^ 0xabcdef1234567ull));
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

const char* extensionOf(SynthEncoding encoding) {
    return encoding == SynthEncoding::kExr ? ".exr" : ".png";
}

image::PixelFormat formatOf(SynthEncoding encoding) {
    switch (encoding) {
        case SynthEncoding::kLinear16:
            return image::PixelFormat::kUint16;
        case SynthEncoding::kExr:
            return image::PixelFormat::kFloat;
        case SynthEncoding::kSrgb8:
            return image::PixelFormat::kUint8;
    }
    return image::PixelFormat::kFloat;
}

nlohmann::json vectorJson(const proto::Vec3d& v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

// Writes one capture.json: the pinhole camera, the rig's lights, the truth's geometry.
void writeManifest(const std::filesystem::path& folder, const PotteryScene& scene,
                   const LightRig& rig, const std::vector<proto::Vec3d>& lights,
                   const std::vector<std::string>& files, SynthEncoding encoding) {
    const capture::PinholeCamera& camera = scene.camera();
    nlohmann::json manifest;
    manifest["format"] = "vpe-capture";
    manifest["version"] = 1;
    manifest["encoding"] = encoding == SynthEncoding::kSrgb8 ? "srgb" : "linear";
    manifest["texel_mm"] = scene.texelMillimetres();
    manifest["camera"] = {{"model", "pinhole"},
                          {"fx", camera.fx},
                          {"fy", camera.fy},
                          {"cx", camera.cx},
                          {"cy", camera.cy},
                          {"rotation", camera.rotation},
                          {"translation", vectorJson(camera.translation)}};
    if (rig.kind == capture::LightKind::kPoint) {
        manifest["lights"] = {{"type", "point"}, {"reference_distance", rig.referenceDistance}};
    } else {
        manifest["lights"] = {{"type", "directional"}};
    }
    manifest["normals"] = {{"file", "../truth/normals.exr"}, {"encoding", "raw"}};
    manifest["positions"] = "../truth/positions.exr";
    manifest["mask"] = "../truth/mask.png";
    manifest["images"] = nlohmann::json::array();
    for (std::size_t i = 0; i < lights.size(); ++i) {
        manifest["images"].push_back({{"file", files[i]}, {"light", vectorJson(lights[i])}});
    }
    proto::writeTextFileAtomically(folder / "capture.json", manifest.dump(1) + "\n");
}

void checkOptions(const SynthOptions& options) {
    if (options.size < 8 || options.size > 4096) {
        throw common::InputError("--size " + std::to_string(options.size) +
                                 " is out of range (8..4096)");
    }
    if (options.rig != "paper" && options.rig != "dome") {
        throw common::InputError("--rig must be paper or dome, not '" + options.rig + "'");
    }
    if (options.fourierHarmonics < 0 || options.fourierHarmonics > proto::kMaxHarmonics) {
        throw common::InputError("--fourier-harmonics is out of range (0.." +
                                 std::to_string(proto::kMaxHarmonics) + ")");
    }
}

// The scene's surface under every pixel, traced once for all lights.
std::vector<SurfacePoint> traceSurface(const PotteryScene& scene, int n, unsigned threads) {
    std::vector<SurfacePoint> surface(static_cast<std::size_t>(n) * n, SurfacePoint{});
    common::parallelFor(static_cast<std::size_t>(n), 4, threads,
                        [&](std::size_t begin, std::size_t end) {
                            for (std::size_t y = begin; y < end; ++y) {
                                for (int x = 0; x < n; ++x) {
                                    surface[y * n + static_cast<std::size_t>(x)] =
                                        scene.surfaceAt(x, static_cast<int>(y));
                                }
                            }
                        });
    return surface;
}

// The Fourier-family truth per pixel and channel (k coefficients each), or empty for the
// microfacet reflectance.
std::vector<double> fourierTruth(const SynthOptions& options,
                                 const std::vector<SurfacePoint>& surface) {
    if (options.reflectance != SynthReflectance::kFourier) {
        return {};
    }
    const int k = proto::coefficientCount(options.fourierHarmonics);
    std::vector<double> fourier(surface.size() * 3 * static_cast<std::size_t>(k), 0.0);
    for (std::size_t p = 0; p < surface.size(); ++p) {
        for (int c = 0; c < 3; ++c) {
            fourierCoefficients(surface[p].material, options.fourierHarmonics, c,
                                &fourier[(p * 3 + static_cast<std::size_t>(c)) * k]);
        }
    }
    return fourier;
}

// Renders the capture's images, light by light, and counts what the report states.
class CaptureRenderer {
public:
    CaptureRenderer(const SynthOptions& options, const PotteryScene& scene, const LightRig& rig,
                    const std::vector<SurfacePoint>& surface, const std::vector<double>& fourier,
                    common::ProgressBar& progress)
        : options_(options),
          scene_(scene),
          rig_(rig),
          surface_(surface),
          fourier_(fourier),
          progress_(progress),
          camera_(scene.cameraCenter()),
          n_(options.size),
          k_(proto::coefficientCount(options.fourierHarmonics)) {}

    // Writes one image per light into `folder` and its capture.json; setKey seeds its noise.
    void renderSet(const std::vector<proto::Vec3d>& lights, const std::filesystem::path& folder,
                   std::uint64_t setKey) {
        const std::size_t pixels = surface_.size();
        const std::string extension = extensionOf(options_.encoding);
        std::vector<std::string> files(lights.size());
        common::parallelFor(
            lights.size(), 1, options_.threads, [&](std::size_t begin, std::size_t end) {
                std::vector<float> image(pixels * 3);
                for (std::size_t i = begin; i < end; ++i) {
                    Counts counts;
                    const std::uint64_t imageKey =
                        common::mixBits(options_.seed ^ common::mixBits(setKey + i));
                    for (std::size_t p = 0; p < pixels; ++p) {
                        shade(p, lights[i], imageKey, counts, &image[p * 3]);
                    }
                    char name[32];
                    std::snprintf(name, sizeof name, "light%03zu", i);
                    files[i] = std::string(name) + extension;
                    image::writeImage(folder / files[i], n_, n_, 3, image,
                                      formatOf(options_.encoding));
                    shadowed_ += counts.shadowed;
                    lit_ += counts.lit;
                    clipped_ += counts.clipped;
                    samples_ += pixels * 3;
                    progress_.advance();
                }
            });
        writeManifest(folder, scene_, rig_, lights, files, options_.encoding);
    }

    double shadowedFraction() const {
        return lit_ ? static_cast<double>(shadowed_) / static_cast<double>(lit_) : 0.0;
    }
    double clippedFraction() const {
        return samples_ ? static_cast<double>(clipped_) / static_cast<double>(samples_) : 0.0;
    }

private:
    struct Counts {
        std::uint64_t shadowed = 0, lit = 0, clipped = 0;
    };

    // Pixel p's encoded RGB under one light (black off the object and in the relief's
    // shadows, as in a dark capture room; camera noise still applies).
    void shade(std::size_t p, proto::Vec3d toLight, std::uint64_t imageKey, Counts& counts,
               float* rgb) const {
        const SurfacePoint& s = surface_[p];
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        if (!s.hit) {
            return;
        }
        double irradiance = 1.0;
        if (rig_.kind == capture::LightKind::kPoint) {
            const proto::Vec3d d{toLight.x - s.position.x, toLight.y - s.position.y,
                                 toLight.z - s.position.z};
            irradiance = rig_.referenceDistance * rig_.referenceDistance / proto::dot(d, d);
            toLight = proto::normalized(d);
        }
        const proto::Vec3d toViewer = proto::normalized(proto::Vec3d{
            camera_.x - s.position.x, camera_.y - s.position.y, camera_.z - s.position.z});
        const bool facing = proto::dot(s.normal, toLight) > 0;
        counts.lit += facing ? 1 : 0;
        const bool inShadow = options_.shadows && facing && scene_.reliefShadows(s, toLight);
        counts.shadowed += inShadow ? 1 : 0;
        double value[3] = {0, 0, 0};
        if (inShadow) {
            // no direct light
        } else if (fourier_.empty()) {
            const proto::Vec3d radiance =
                microfacetRadiance(s.material, s.normal, toLight, toViewer);
            value[0] = radiance.x;
            value[1] = radiance.y;
            value[2] = radiance.z;
        } else {
            const auto angles = proto::reflectionAngles(s.normal, toLight, toViewer);
            for (int c = 0; c < 3; ++c) {
                value[c] = proto::evaluateFourierBrdf(
                    &fourier_[(p * 3 + static_cast<std::size_t>(c)) * k_],
                    options_.fourierHarmonics, angles.cosThetaD, angles.cosThetaS);
            }
        }
        for (int c = 0; c < 3; ++c) {
            double y = irradiance * value[c];
            if (options_.noise == SynthNoise::kCamera) {
                const std::uint64_t key =
                    imageKey ^ common::mixBits(p * 3 + static_cast<std::size_t>(c));
                y += std::sqrt(std::max(y, 0.0) / kFullWell + kReadNoise * kReadNoise) *
                     gaussian(key);
            }
            if (options_.encoding == SynthEncoding::kSrgb8) {
                y = proto::linearToSrgb(std::clamp(y, 0.0, 1.0));
            }
            counts.clipped += y >= 1.0 ? 1 : 0;
            rgb[c] = static_cast<float>(y);
        }
    }

    const SynthOptions& options_;
    const PotteryScene& scene_;
    const LightRig& rig_;
    const std::vector<SurfacePoint>& surface_;
    const std::vector<double>& fourier_;
    common::ProgressBar& progress_;
    proto::Vec3d camera_;
    int n_, k_;
    std::atomic<std::uint64_t> shadowed_{0}, lit_{0}, clipped_{0}, samples_{0};
};

// Writes truth/: geometry, labels, the material parameters and a mask; returns the share of
// the object's pixels labelled streak.
double writeTruthImages(const std::filesystem::path& truth,
                        const std::vector<SurfacePoint>& surface, int n) {
    const std::size_t pixels = surface.size();
    std::vector<float> normals(pixels * 3), normalsPreview(pixels * 3), positions(pixels * 3),
        macroNormals(pixels * 3), parameters(pixels * 8), labels(pixels), labelsPreview(pixels * 3),
        mask(pixels);
    std::size_t streakPixels = 0, hitPixels = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        const SurfacePoint& s = surface[p];
        const double n3[3] = {s.normal.x, s.normal.y, s.normal.z};
        const double p3[3] = {s.position.x, s.position.y, s.position.z};
        const double m3[3] = {s.baseNormal.x, s.baseNormal.y, s.baseNormal.z};
        for (int c = 0; c < 3; ++c) {
            normals[p * 3 + c] = s.hit ? static_cast<float>(n3[c]) : 0.0f;
            macroNormals[p * 3 + c] = s.hit ? static_cast<float>(m3[c]) : 0.0f;
            normalsPreview[p * 3 + c] = s.hit ? static_cast<float>((n3[c] + 1) / 2) : 0.0f;
            positions[p * 3 + c] = static_cast<float>(p3[c]);
        }
        const double values[8] = {s.material.albedo.x,
                                  s.material.albedo.y,
                                  s.material.albedo.z,
                                  s.material.roughness,
                                  s.material.f0,
                                  static_cast<double>(s.label),
                                  s.relief,
                                  s.streak};
        for (int c = 0; c < 8; ++c) {
            parameters[p * 8 + c] = s.hit ? static_cast<float>(values[c]) : 0.0f;
        }
        labels[p] = static_cast<float>(s.label) / 255.0f;  // label index as the 8-bit value
        const proto::Vec3d colour =
            s.label ? proto::Vec3d{0.75, 0.22, 0.12} : proto::Vec3d{0.80, 0.70, 0.52};
        labelsPreview[p * 3] = static_cast<float>(colour.x);
        labelsPreview[p * 3 + 1] = static_cast<float>(colour.y);
        labelsPreview[p * 3 + 2] = static_cast<float>(colour.z);
        mask[p] = s.hit ? 1.0f : 0.0f;
        streakPixels += s.hit && s.label ? 1 : 0;
        hitPixels += s.hit ? 1 : 0;
    }
    image::writeImage(truth / "normals.exr", n, n, 3, normals, image::PixelFormat::kFloat);
    image::writeImage(truth / "normals.png", n, n, 3, normalsPreview, image::PixelFormat::kUint8);
    // The smooth surface of revolution's normals: the macro shape the relief tilts.
    image::writeImage(truth / "macro-normals.exr", n, n, 3, macroNormals,
                      image::PixelFormat::kFloat);
    image::writeImage(truth / "positions.exr", n, n, 3, positions, image::PixelFormat::kFloat);
    image::writeImage(truth / "parameters.exr", n, n, 8, parameters, image::PixelFormat::kFloat);
    image::writeImage(truth / "labels.png", n, n, 1, labels, image::PixelFormat::kUint8);
    image::writeImage(truth / "labels-preview.png", n, n, 3, labelsPreview,
                      image::PixelFormat::kUint8);
    image::writeImage(truth / "mask.png", n, n, 1, mask, image::PixelFormat::kUint8);
    return hitPixels ? static_cast<double>(streakPixels) / hitPixels : 0.0;
}

// truth/fourier.exr: the Fourier-family truth as a model file.
void writeFourierTruth(const std::filesystem::path& truth, const std::vector<SurfacePoint>& surface,
                       const std::vector<double>& fourier, int harmonics, int n, double texelMm) {
    const int k = proto::coefficientCount(harmonics);
    model::ModelInfo info;
    info.width = info.height = n;
    info.harmonics = harmonics;
    info.samples = 0;
    info.capture = "vpe synth --reflectance fourier (the truth)";
    info.texelMm = texelMm;
    model::ModelWriter writer(truth / "fourier.exr", info);
    model::ModelRows rows;
    rows.resize(n, n, k);
    for (std::size_t p = 0; p < surface.size(); ++p) {
        rows.valid[p] = surface[p].hit ? 1 : 0;
        const double n3[3] = {surface[p].normal.x, surface[p].normal.y, surface[p].normal.z};
        for (int c = 0; c < 3; ++c) {
            rows.normal[p * 3 + c] = static_cast<float>(n3[c]);
        }
        for (std::size_t i = 0; i < 3 * static_cast<std::size_t>(k); ++i) {
            rows.coefficient[p * 3 * k + i] = static_cast<float>(fourier[p * 3 * k + i]);
        }
    }
    writer.writeRows(0, rows);
    writer.finish();
}

// truth/synth.json: how the capture was made.
nlohmann::json describeCapture(const SynthOptions& options, const PotteryScene& scene,
                               const LightRig& rig, bool fourier) {
    nlohmann::json description;
    description["generator"] = "vpe synth";
    description["seed"] = options.seed;
    description["size"] = options.size;
    description["millimetres_per_unit"] = PotteryScene::kMillimetresPerUnit;
    description["texel_mm"] = scene.texelMillimetres();
    description["rig"] = rig.name;
    description["noise"] = options.noise == SynthNoise::kCamera ? "camera" : "none";
    description["shadows"] = options.shadows;
    description["encoding"] = options.encoding == SynthEncoding::kExr     ? "exr"
                              : options.encoding == SynthEncoding::kSrgb8 ? "srgb8"
                                                                          : "linear16";
    description["reflectance"] = fourier ? "fourier" : "microfacet";
    description["parameters_channels"] = {"albedo.R", "albedo.G", "albedo.B", "roughness",
                                          "f0",       "label",    "relief",   "streak"};
    description["labels"] = {"ground", "streak"};
    description["lights"] = {
        {"kind", rig.kind == capture::LightKind::kPoint ? "point" : "directional"},
        {"reference_distance", rig.referenceDistance},
        {"train", nlohmann::json::array()},
        {"test", nlohmann::json::array()}};
    for (const proto::Vec3d& l : rig.train) {
        description["lights"]["train"].push_back(vectorJson(l));
    }
    for (const proto::Vec3d& l : rig.test) {
        description["lights"]["test"].push_back(vectorJson(l));
    }
    return description;
}

}  // namespace

SynthReport synthesizeCapture(const SynthOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    checkOptions(options);
    // Everything is written beside DIR and swapped in at the end.
    common::AtomicFolder output(options.out, std::filesystem::path("truth") / "synth.json",
                                "vpe synth");
    const std::filesystem::path& partial = output.temporaryPath();
    for (const char* folder : {"train", "test", "truth"}) {
        std::filesystem::create_directories(partial / folder);
    }

    const PotteryScene scene(options.size, options.seed);
    const LightRig rig = options.rig == "paper" ? paperRig() : domeRig();
    const std::vector<SurfacePoint> surface = traceSurface(scene, options.size, options.threads);
    const std::vector<double> fourier = fourierTruth(options, surface);

    common::ProgressBar progress("synth", rig.train.size() + rig.test.size());
    CaptureRenderer renderer(options, scene, rig, surface, fourier, progress);
    renderer.renderSet(rig.train, partial / "train", 1);
    renderer.renderSet(rig.test, partial / "test", 1000000);
    progress.finish();

    const std::filesystem::path truth = partial / "truth";
    SynthReport report;
    report.size = options.size;
    report.trainImages = static_cast<int>(rig.train.size());
    report.testImages = static_cast<int>(rig.test.size());
    report.streakFraction = writeTruthImages(truth, surface, options.size);
    if (!fourier.empty()) {
        writeFourierTruth(truth, surface, fourier, options.fourierHarmonics, options.size,
                          scene.texelMillimetres());
    }
    proto::writeTextFileAtomically(
        truth / "synth.json",
        describeCapture(options, scene, rig, !fourier.empty()).dump(1) + "\n");
    // Swap the finished capture into place.
    output.commit();

    report.shadowedFraction = renderer.shadowedFraction();
    report.clippedFraction = renderer.clippedFraction();
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace vpe::synth
