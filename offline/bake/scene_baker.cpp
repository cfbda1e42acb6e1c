// SPDX-License-Identifier: MIT
// vpe bake: reads and checks the inputs, encodes the textures, fits the θs basis to what the
// device will render, and writes the bundle.
#include "vpe/bake/scene_baker.h"

#include <algorithm>
#include <cmath>

#include "vpe/bake/bake_inputs.h"
#include "vpe/bake/bundle_render_mesh.h"
#include "vpe/bake/bundle_writer.h"
#include "vpe/bake/low_rank_encoder.h"
#include "vpe/bake/measured_light_maps.h"
#include "vpe/bake/theta_basis_fit.h"
#include "vpe/common/input_error.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/registration/mesh_registration.h"
#include "vpe/scan/scan_files.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/surface_scale.h"
#include "vpe/texture/region_compose.h"
#include "vpe/texture/weight_maps.h"

namespace vpe::bake {

namespace {

// K when --theta-basis is not given: the demo's measured knee (proto/MODEL.md's K curve).
constexpr int kDefaultThetaBasis = 4;

// The θs basis's size for textures of M harmonics (BakeOptions::thetaBasis).
int thetaBasisSize(const std::optional<int>& requested, int harmonics) {
    const int independent = independentThetaFunctions(harmonics);
    if (!requested) {
        return std::min(kDefaultThetaBasis, independent);
    }
    const int size = *requested;
    const std::string option = "--theta-basis " + std::to_string(size);
    const int functions = proto::thetaFunctionCount(harmonics);
    if (size < 0) {
        throw common::InputError(option + ": not a number of functions (give 1.." +
                                 std::to_string(independent) + ", or full)");
    }
    if (size > functions) {
        throw common::InputError(option + ": more than the 2M + 1 = " + std::to_string(functions) +
                                 " θs functions of the textures (M = " + std::to_string(harmonics) +
                                 ")");
    }
    if (size > independent) {
        throw common::InputError(option + ": only " + std::to_string(independent) + " of the " +
                                 std::to_string(functions) +
                                 " θs functions of M = " + std::to_string(harmonics) +
                                 " are independent over [0, π] (give at most " +
                                 std::to_string(independent) + ", or full)");
    }
    return size;
}

// Encodes a texture and adds what the device will render of it — the decoded low-rank code,
// or the full coefficients — to the θs moment (when a basis is wanted).
CoefficientMapData encodeMap(const model::CoefficientImage& texture, const BakeOptions& options,
                             ThetaMoment* moment, BakeReport& report) {
    CoefficientMapData map;
    const std::vector<float> values = bundleCoefficients(texture);
    if (options.relief) {
        map.detailNormals = bundleDetailNormals(texture);
        report.relief = report.relief || !map.detailNormals.empty();
    }
    if (!options.lowRank) {
        map.encoding = proto::CoefficientEncoding::kFull;
        map.coefficients = values;
        if (moment != nullptr) {
            moment->add(map.coefficients, texture.valid);
        }
        return map;
    }
    const int channels = 3 * proto::coefficientCount(texture.harmonics);
    LowRankOptions lowRank;
    lowRank.rank = std::min(options.rank, channels);
    lowRank.threads = options.threads;
    LowRankCode code = encodeLowRank(values, channels, texture.valid, lowRank);
    double kept = 0;
    for (double share : code.explained) {
        kept += share;
    }
    report.explainedVariance = std::min(report.explainedVariance, kept);
    const std::vector<float> decoded = decodeLowRank(code);
    if (moment != nullptr) {
        moment->add(decoded, texture.valid);
    }
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t t = 0; t < texture.valid.size(); ++t) {
        if (!texture.valid[t]) {
            continue;
        }
        for (int k = 0; k < channels; ++k) {
            const std::size_t i =
                t * static_cast<std::size_t>(channels) + static_cast<std::size_t>(k);
            const double d = static_cast<double>(decoded[i]) - static_cast<double>(values[i]);
            sum += d * d;
        }
        count += static_cast<std::size_t>(channels);
    }
    report.coefficientRms =
        std::max(report.coefficientRms, count ? std::sqrt(sum / static_cast<double>(count)) : 0.0);
    map.encoding = proto::CoefficientEncoding::kLowRank;
    map.rank = code.rank;
    map.mean = std::move(code.mean);
    map.basis = std::move(code.basis);
    map.weights = std::move(code.weights);
    return map;
}

// Where a projector stands: its calibration and the camera's in the object frame, the mesh
// (placed by a scan, when there is one).
struct ProjectorPlacement {
    scene::ProjectorCalibration projector;
    std::optional<proto::PinholeCamera> camera;
    scene::ScreenMesh mesh;
    std::optional<ScanPlacement> placement;
};

scene::ScreenMesh loadMesh(const BakeOptions& options) {
    if (options.mesh.empty()) {
        return scene::makeProceduralVase();
    }
    scene::ScreenMeshLoadOptions load;
    load.metresPerUnit = options.meshMetresPerUnit;
    return scene::loadScreenMesh(options.mesh, load);
}

// The projector of a calibration file (or the demo one when there is none) or of a scan.
ProjectorPlacement placeProjector(const BakeOptions& options,
                                  const std::filesystem::path& projector,
                                  const std::filesystem::path& scan) {
    if (!scan.empty() && !projector.empty()) {
        throw common::InputError("bake: --scan brings its own calibration; leave out --projector");
    }
    ProjectorPlacement placed;
    placed.camera = options.camera;
    if (!scan.empty()) {
        std::optional<scene::ScreenMesh> given;
        if (!options.mesh.empty()) {
            given = loadMesh(options);
        }
        placed.placement = placeFromScan(scan, given, options.registration);
        placed.projector = placed.placement->projector;
        placed.camera = placed.placement->camera;
        placed.mesh = placed.placement->mesh;
        return placed;
    }
    if (projector.empty()) {
        placed.projector = scene::makeDemoProjector(options.demoDistance);
    } else {
        scene::ProjectorCalibrationOverrides overrides;
        overrides.width = options.projectorWidth;
        overrides.height = options.projectorHeight;
        overrides.metresPerUnit = options.projectorMetresPerUnit;
        placed.projector = scene::readProjectorCalibration(projector, overrides);
    }
    if (placed.camera) {
        scene::validateCameraCalibration(*placed.camera, "camera");
    } else if (!projector.empty()) {
        placed.camera = scene::readCameraCalibration(projector);
    }
    placed.mesh = loadMesh(options);
    return placed;
}

// The projector's part of a bundle: its calibration, the camera, the response, and the light
// measured on site when there is one.
void addProjector(BundleContents& contents, const ProjectorPlacement& placed,
                  const BakeOptions& options, const std::filesystem::path& radiometryFolder,
                  BakeReport& report) {
    contents.projector = toBundleProjector(placed.projector);
    contents.camera.reset();
    if (placed.camera) {
        contents.camera = toBundleProjector(*placed.camera);
    }
    contents.settings = options.settings;
    contents.settings.response = toBundleResponse(scene::parseProjectorResponse(options.response));
    contents.radiometry.reset();
    if (!radiometryFolder.empty()) {
        const radiometry::ProjectorRadiometry measured =
            radiometry::readRadiometry(radiometryFolder);
        MeasuredLightBake baked =
            bakeMeasuredLight(measured, contents.mesh, contents.projector, radiometryFolder);
        contents.radiometry = std::move(baked.radiometry);
        report.radiometryCovered = baked.covered;
        report.radiometryCompleted = baked.completed;
        // The response above black, at 33 even levels: the measured ladder, linear between.
        contents.settings.response = toBundleResponse(
            scene::readProjectorResponseCsv(radiometryFolder / radiometry::kResponseFile), 33);
        contents.settings.ambientIrradiance = {0, 0, 0};
    }
    report.placement = placed.placement;
    report.camera = placed.camera.has_value();
    if (placed.camera) {
        report.cameraWidth = placed.camera->width;
        report.cameraHeight = placed.camera->height;
    }
}

// The textures, the model and the weight presets: what every projector's bundle shares.
void addTextures(BundleContents& contents, const BakeOptions& options,
                 const scene::ScreenMesh& mesh, BakeReport& report) {
    report.vertices = mesh.vertexCount();
    report.triangles = mesh.triangleCount();
    std::vector<model::CoefficientImage> textures;
    std::vector<std::string> names;
    if (!options.texture.empty()) {
        textures.push_back(model::readCoefficientImage(options.texture));
        names.push_back(options.texture.stem().string());
    } else {
        const std::vector<std::filesystem::path> maps = quilt::listRegionMaps(options.quilt);
        texture::checkRegionMaps(maps);
        for (std::size_t r = 0; r < maps.size(); ++r) {
            textures.push_back(model::readCoefficientImage(maps[r]));
            names.push_back("region" + std::to_string(r));
        }
    }
    const model::CoefficientImage& first = textures.front();
    contents.textureWidth = first.width;
    contents.textureHeight = first.height;
    // Sampling wraps in u only when every map tiles: one that does not would blend its two
    // unrelated edges.
    contents.textureWrapsU = std::all_of(textures.begin(), textures.end(),
                                         [](const model::CoefficientImage& t) { return t.tilesU; });
    report.wrapU = contents.textureWrapsU;
    report.meshWrapsU = scene::measureSurfaceScale(mesh).wrapsU;
    contents.model.harmonics = first.harmonics;
    contents.model.lambda = first.lambda;
    const int thetaSize = thetaBasisSize(options.thetaBasis, first.harmonics);
    ThetaMoment moment(first.harmonics);
    for (std::size_t r = 0; r < textures.size(); ++r) {
        contents.regions.push_back(
            {names[r], encodeMap(textures[r], options, thetaSize > 0 ? &moment : nullptr, report)});
    }
    if (thetaSize > 0) {
        ThetaBasisFit fit;
        try {
            fit = fitThetaBasis(moment, thetaSize);
        } catch (const common::InputError& error) {
            throw common::InputError("--theta-basis " + std::to_string(thetaSize) + ": " +
                                     error.what());
        }
        contents.model.thetaBasis = std::move(fit.functions);
        report.thetaBasis = thetaSize;
        report.thetaEnergyKept = fit.energyKept;
    }
    if (options.presets.empty()) {
        contents.presets.push_back(
            {"single", proto::AlphaEncoding::kUnorm8,
             std::vector<float>(static_cast<std::size_t>(first.width) * first.height, 1.0f)});
    }
    for (const PresetSpec& preset : options.presets) {
        const std::string origin = "--preset " + preset.name;
        const std::vector<texture::WeightSource> sources =
            texture::parseWeightSpec(preset.weights, origin);
        if (sources.size() != textures.size()) {
            throw common::InputError(origin + ": " + std::to_string(sources.size()) +
                                     " weight entries for " + std::to_string(textures.size()) +
                                     " regions (one per region)");
        }
        const texture::WeightMaps weights =
            texture::buildWeightMaps(sources, first.width, first.height);
        WeightPreset baked;
        baked.name = preset.name;
        baked.encoding = proto::AlphaEncoding::kUnorm8;
        for (const std::vector<float>& alpha : weights.alpha) {
            baked.alpha.insert(baked.alpha.end(), alpha.begin(), alpha.end());
        }
        contents.presets.push_back(std::move(baked));
    }
    report.textureWidth = first.width;
    report.textureHeight = first.height;
    report.harmonics = first.harmonics;
    report.regions = static_cast<int>(textures.size());
    const int perTexel = options.lowRank
                             ? std::min(options.rank, contents.model.coefficientsPerTexel())
                             : contents.model.coefficientsPerTexel();
    report.bytesPerTexel = 8 * ((perTexel + 3) / 4);
}

void checkTextureOptions(const BakeOptions& options) {
    if (options.texture.empty() == options.quilt.empty()) {
        throw common::InputError("bake: give either --texture MODEL.exr or --quilt DIR");
    }
    if (!options.quilt.empty() && options.presets.empty()) {
        throw common::InputError("bake: --quilt needs at least one --preset NAME=WEIGHTS");
    }
    if (!options.texture.empty() && !options.presets.empty()) {
        throw common::InputError(
            "bake: --preset goes with --quilt (a composed --texture has one region)");
    }
}

void write(const std::filesystem::path& out, const BundleContents& contents, BakeReport& report) {
    const BundleWriteResult written = writeBundle(out, contents);
    report.bytes = written.bytes;
    report.checksum = written.checksum;
}

}  // namespace

BakeReport bakeScene(const BakeOptions& options, const std::filesystem::path& out) {
    checkTextureOptions(options);
    // Cheap checks first: the projector and the response, then the mesh, then the textures.
    const ProjectorPlacement placed = placeProjector(options, options.projector, options.scan);
    BakeReport report;
    BundleContents contents;
    contents.mesh = toBundleMesh(placed.mesh);
    addProjector(contents, placed, options, options.radiometry, report);
    addTextures(contents, options, placed.mesh, report);
    write(out, contents, report);
    return report;
}

ShowReport bakeShow(const BakeOptions& options, const std::vector<ShowProjector>& projectors,
                    const BlendOptions& blendOptions) {
    checkTextureOptions(options);
    if (projectors.empty()) {
        throw common::InputError("bake: a show needs at least one projector");
    }
    std::vector<ProjectorPlacement> placed;
    for (const ShowProjector& projector : projectors) {
        if (projector.scan.empty() || placed.empty() || !placed.front().placement) {
            placed.push_back(placeProjector(options, projector.calibration, projector.scan));
            continue;
        }
        // One camera saw every projector's patterns: the first scan's registration places the
        // object; this scan's calibration (camera → projector) carries its projector there.
        if (!projector.calibration.empty()) {
            throw common::InputError(
                "bake: --scan brings its own calibration; leave out --projector");
        }
        const std::filesystem::path file = projector.scan / scan::kCalibrationFile;
        ProjectorPlacement next = placed.front();
        next.projector = registration::inObjectFrame(scene::readProjectorCalibration(file),
                                                     next.placement->objectToCamera);
        next.placement->projector = next.projector;
        placed.push_back(std::move(next));
    }
    if (!placed.front().placement) {
        for (const ProjectorPlacement& p : placed) {
            if (p.placement) {
                throw common::InputError(
                    "bake: the first projector of a show with scans must be a scan "
                    "(its registration places the object for all)");
            }
        }
    }
    BundleContents contents;
    contents.mesh = toBundleMesh(placed.front().mesh);
    BakeReport shared;
    addTextures(contents, options, placed.front().mesh, shared);

    const BundleRenderMesh mesh(contents.mesh);
    std::vector<renderer::ProjectorModel> models;
    for (const ProjectorPlacement& p : placed) {
        renderer::ProjectorModel model;
        model.camera = p.projector;
        model.peakIrradiance = static_cast<double>(options.settings.peakIrradiance);
        models.push_back(model);
    }
    ShowReport show;
    show.blend = blendProjectors(mesh.view, models, blendOptions);
    for (std::size_t i = 0; i < placed.size(); ++i) {
        BakeReport report = shared;
        addProjector(contents, placed[i], options, projectors[i].radiometry, report);
        contents.blend = BundleBlend{static_cast<int>(placed.size()), static_cast<int>(i),
                                     show.blend.shares[i].values};
        write(projectors[i].out, contents, report);
        show.bundles.push_back(std::move(report));
    }
    return show;
}

}  // namespace vpe::bake
