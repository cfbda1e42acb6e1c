// SPDX-License-Identifier: MIT
// vpe bake: reads and checks the inputs, encodes the textures, fits the θs basis to what the
// device will render, and writes the bundle.
#include "vpe/bake/scene_baker.h"

#include <algorithm>
#include <cmath>

#include "vpe/bake/bake_inputs.h"
#include "vpe/bake/bundle_writer.h"
#include "vpe/bake/low_rank_encoder.h"
#include "vpe/bake/measured_light_maps.h"
#include "vpe/bake/theta_basis_fit.h"
#include "vpe/common/input_error.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/quilt/quilt_folder.h"
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
        throw InputError(option + ": not a number of functions (give 1.." +
                         std::to_string(independent) + ", or full)");
    }
    if (size > functions) {
        throw InputError(option + ": more than the 2M + 1 = " + std::to_string(functions) +
                         " θs functions of the textures (M = " + std::to_string(harmonics) + ")");
    }
    if (size > independent) {
        throw InputError(option + ": only " + std::to_string(independent) + " of the " +
                         std::to_string(functions) + " θs functions of M = " +
                         std::to_string(harmonics) + " are independent over [0, π] (give at most " +
                         std::to_string(independent) + ", or full)");
    }
    return size;
}

// Encodes a texture and adds what the device will render of it — the decoded low-rank code,
// or the full coefficients — to the θs moment (when a basis is wanted).
CoefficientMapData encodeMap(const CoefficientTexture& texture, const BakeOptions& options,
                             ThetaMoment* moment, BakeReport& report) {
    CoefficientMapData map;
    if (options.relief) {
        map.detailNormals = texture.detailNormals;
        report.relief = report.relief || !map.detailNormals.empty();
    }
    if (!options.lowRank) {
        map.encoding = proto::CoefficientEncoding::kFull;
        map.coefficients = texture.values;
        if (moment != nullptr) {
            moment->add(map.coefficients, texture.valid);
        }
        return map;
    }
    const int channels = 3 * proto::coefficientCount(texture.harmonics);
    LowRankOptions lowRank;
    lowRank.rank = std::min(options.rank, channels);
    lowRank.threads = options.threads;
    LowRankCode code = encodeLowRank(texture.values, channels, texture.valid, lowRank);
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
            const double d =
                static_cast<double>(decoded[i]) - static_cast<double>(texture.values[i]);
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

}  // namespace

BakeReport bakeScene(const BakeOptions& options, const std::filesystem::path& out) {
    if (options.texture.empty() == options.quilt.empty()) {
        throw InputError("bake: give either --texture MODEL.exr or --quilt DIR");
    }
    if (!options.quilt.empty() && options.presets.empty()) {
        throw InputError("bake: --quilt needs at least one --preset NAME=WEIGHTS");
    }
    if (!options.texture.empty() && !options.presets.empty()) {
        throw InputError("bake: --preset goes with --quilt (a composed --texture has one region)");
    }
    // Cheap checks first: the projector and the response, then the mesh, then the textures.
    if (!options.scan.empty() && !options.projector.empty()) {
        throw InputError("bake: --scan brings its own calibration; leave out --projector");
    }
    BundleContents contents;
    std::optional<ScanPlacement> placement;
    scene::ProjectorCalibration projector;
    std::optional<proto::PinholeCamera> camera = options.camera;
    scene::ScreenMesh mesh;
    if (!options.scan.empty()) {
        std::optional<scene::ScreenMesh> given;
        if (!options.mesh.empty()) {
            scene::ScreenMeshLoadOptions load;
            load.metresPerUnit = options.meshMetresPerUnit;
            given = scene::loadScreenMesh(options.mesh, load);
        }
        placement = placeFromScan(options.scan, given, options.registration);
        projector = placement->projector;
        camera = placement->camera;
        mesh = placement->mesh;
    } else if (options.projector.empty()) {
        projector = scene::makeDemoProjector(options.demoDistance);
    } else {
        scene::ProjectorCalibrationOverrides overrides;
        overrides.width = options.projectorWidth;
        overrides.height = options.projectorHeight;
        overrides.metresPerUnit = options.projectorMetresPerUnit;
        projector = scene::readProjectorCalibration(options.projector, overrides);
    }
    contents.projector = toBundleProjector(projector);
    if (camera) {
        scene::validateCameraCalibration(*camera, "camera");
    } else if (!options.projector.empty()) {
        camera = scene::readCameraCalibration(options.projector);
    }
    if (camera) {
        contents.camera = toBundleProjector(*camera);
    }
    contents.settings = options.settings;
    contents.settings.response = toBundleResponse(scene::parseProjectorResponse(options.response));

    if (!placement) {  // a scan placed its mesh above
        if (options.mesh.empty()) {
            mesh = scene::makeProceduralVase();
        } else {
            scene::ScreenMeshLoadOptions load;
            load.metresPerUnit = options.meshMetresPerUnit;
            mesh = scene::loadScreenMesh(options.mesh, load);
        }
    }
    contents.mesh = toBundleMesh(mesh);
    BakeReport report;
    if (!options.radiometry.empty()) {
        const radiometry::ProjectorRadiometry measured =
            radiometry::readRadiometry(options.radiometry);
        MeasuredLightBake baked =
            bakeMeasuredLight(measured, contents.mesh, contents.projector, options.radiometry);
        contents.radiometry = std::move(baked.radiometry);
        report.radiometryCovered = baked.covered;
        report.radiometryCompleted = baked.completed;
        // The response above black, at 33 even levels: the measured ladder, linear between.
        contents.settings.response = toBundleResponse(
            scene::readProjectorResponseCsv(options.radiometry / radiometry::kResponseFile), 33);
        contents.settings.ambientIrradiance = {0, 0, 0};
    }

    report.placement = placement;
    report.vertices = mesh.vertexCount();
    report.triangles = mesh.triangleCount();
    std::vector<CoefficientTexture> textures;
    std::vector<std::string> names;
    if (!options.texture.empty()) {
        textures.push_back(readCoefficientTexture(options.texture));
        names.push_back(options.texture.stem().string());
    } else {
        const std::vector<std::filesystem::path> maps = quilt::listRegionMaps(options.quilt);
        texture::checkRegionMaps(maps);
        for (std::size_t r = 0; r < maps.size(); ++r) {
            textures.push_back(readCoefficientTexture(maps[r]));
            names.push_back("region" + std::to_string(r));
        }
    }
    const CoefficientTexture& first = textures.front();
    contents.textureWidth = first.width;
    contents.textureHeight = first.height;
    // Sampling wraps in u only when every map tiles: one that does not would blend its two
    // unrelated edges.
    contents.textureWrapsU = std::all_of(textures.begin(), textures.end(),
                                         [](const CoefficientTexture& t) { return t.tilesU; });
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
        } catch (const InputError& error) {
            throw InputError("--theta-basis " + std::to_string(thetaSize) + ": " + error.what());
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
            throw InputError(origin + ": " + std::to_string(sources.size()) +
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

    const BundleWriteResult written = writeBundle(out, contents);
    report.textureWidth = first.width;
    report.textureHeight = first.height;
    report.harmonics = first.harmonics;
    report.regions = static_cast<int>(textures.size());
    const int perTexel = options.lowRank
                             ? std::min(options.rank, contents.model.coefficientsPerTexel())
                             : contents.model.coefficientsPerTexel();
    report.bytesPerTexel = 8 * ((perTexel + 3) / 4);
    report.bytes = written.bytes;
    report.checksum = written.checksum;
    report.camera = camera.has_value();
    if (camera) {
        report.cameraWidth = camera->width;
        report.cameraHeight = camera->height;
    }
    return report;
}

}  // namespace vpe::bake
