// SPDX-License-Identifier: MIT
// The extended model: geometry calibration and light transport recover what they should.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include "vpe/capture/capture_loader.h"
#include "vpe/capture/geometry_calibration.h"
#include "vpe/eval/model_evaluation.h"
#include "vpe/fit/capture_fitter.h"
#include "vpe/fit/held_out_search.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/light_transport.h"
#include "vpe/normals/normal_map.h"
#include "vpe/normals/photometric_stereo.h"
#include "vpe/proto/fourier_brdf.h"

#include "support/synthetic_capture.h"
#include "support/test_data.h"

namespace vpe {
namespace {

// A glossy material: strong low harmonics make the appearance depend on the view direction.
void glossy(int x, int y, int c, double* k) {
    k[proto::kLambertIndex] = 0.3 + 0.05 * c + 0.002 * x;
    k[proto::kConstantIndex] = 0.02;
    const double lobe[3][2] = {{0.18, 0.0}, {0.10, 0.02}, {0.05, 0.01}};
    for (int m = 1; m <= 3; ++m) {
        k[proto::cosineIndex(m)] = lobe[m - 1][0] * (1.0 + 0.001 * y);
        k[proto::sineIndex(m)] = lobe[m - 1][1];
    }
}

testing::SyntheticCaptureSpec domeSpec(const std::vector<double>& elevations, int perRing,
                                       double azimuthOffset) {
    testing::SyntheticCaptureSpec spec;
    spec.width = 64;
    spec.height = 48;
    spec.harmonics = 3;
    spec.manifest = false;  // a .lp capture: geometry unstated, as RTI domes write it
    spec.lights = testing::domeLights(elevations, perRing, azimuthOffset);
    spec.coefficients = glossy;
    spec.normal = [](int x, int y) {
        return proto::Vec3d{0.3 * std::sin(0.2 * x), 0.3 * std::cos(0.15 * y), 1.0};
    };
    return spec;
}

double heldOutPsnr(const std::filesystem::path& train, const std::filesystem::path& test,
                   const std::filesystem::path& model, fit::ModelVariant variant,
                   bool calibrateResponse = true) {
    fit::FitOptions options;
    options.harmonics = 3;
    options.lambda = 0.1;
    options.variant = variant;
    options.calibrateResponse = calibrateResponse;
    options.writePreview = false;
    fit::fitCapture(capture::openCapture(train), options, model);
    return eval::evaluateModel(model, capture::openCapture(test), eval::EvaluationOptions{}).psnr;
}

// Held-out PSNRs (dB) of the paper model and the extended one, each fitted on folder/train
// (into folder/paper.exr and folder/extended.exr) and measured under folder/test's lights.
struct VariantPsnrs {
    double paper;
    double extended;
};

VariantPsnrs heldOutPsnrsOfBothVariants(const testing::TemporaryFolder& folder) {
    return {heldOutPsnr(folder / "train", folder / "test", folder / "paper.exr",
                        fit::ModelVariant::kPaper),
            heldOutPsnr(folder / "train", folder / "test", folder / "extended.exr",
                        fit::ModelVariant::kExtended)};
}

// The dome seen by a camera of 40° field of view, its lights 5 half-widths away, written to
// folder/train; its true normals; and a search of its geometry alone (M = 3, λ = 0.1) on a grid
// of 128 pixels: measured, the same field of view (42.5°) and distance (5.37) as on 1,024, the
// misfired exposure's included, in a tenth of the time (64 pixels moved the misfired one).
struct GeometrySearchCase {
    capture::Capture capture;
    normals::NormalMap normals;
    fit::HeldOutSearchOptions options;
};

GeometrySearchCase geometrySearchCase(const testing::TemporaryFolder& folder) {
    auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    spec.geometry = {40.0, 5.0, 0.0, {}};
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "train", spec);
    GeometrySearchCase c;
    c.capture = capture::openCapture(folder / "train");
    c.normals = testing::trueNormalMap(truth, spec.width, spec.height);
    c.options.harmonics = 3;
    c.options.lambda = 0.1;
    c.options.selectRegularization = false;
    c.options.samplePixels = 128;
    return c;
}

TEST(ExtendedModel, CalibrationRecoversFieldOfViewAndLightDistance) {
    testing::TemporaryFolder folder;
    const GeometrySearchCase c = geometrySearchCase(folder);
    const fit::HeldOutSearchResult result = fit::searchHeldOut(c.capture, c.normals, c.options);
    EXPECT_NEAR(result.calibration.fieldOfViewDegrees, 40.0, 5.0);
    EXPECT_NEAR(result.calibration.lightDistance, 5.0, 1.0);
    EXPECT_LT(result.rms, 0.25 * result.baselineRms);
}

// The search needs normals on its grid only (the response's second round estimates them
// there alone): a map holding just the grid's pixels gives the same grid and the same scores.
TEST(ExtendedModel, HeldOutSearchRunsOnNormalsOfItsGridAlone) {
    testing::TemporaryFolder folder;
    GeometrySearchCase c = geometrySearchCase(folder);
    const capture::Capture& capture = c.capture;
    const normals::NormalMap& whole = c.normals;
    fit::HeldOutSearchOptions& options = c.options;
    options.samplePixels = 256;
    const std::vector<std::uint8_t> grid = fit::heldOutGridPixels(whole, options.samplePixels);
    const auto taken = static_cast<int>(std::count(grid.begin(), grid.end(), 1));
    EXPECT_GT(taken, 200);
    EXPECT_LT(taken, 400);
    normals::NormalMap alone = whole;
    for (std::size_t p = 0; p < grid.size(); ++p) {
        alone.valid[p] = grid[p];
    }
    EXPECT_EQ(fit::heldOutGridPixels(alone, options.samplePixels), grid);
    EXPECT_EQ(
        fit::heldOutGridPixels(whole.valid, whole.width, whole.height, 1.0, options.samplePixels),
        grid);
    const fit::HeldOutSearchResult onWhole = fit::searchHeldOut(capture, whole, options);
    const fit::HeldOutSearchResult onGrid = fit::searchHeldOut(capture, alone, options);
    EXPECT_EQ(onGrid.calibration.fieldOfViewDegrees, onWhole.calibration.fieldOfViewDegrees);
    EXPECT_EQ(onGrid.calibration.lightDistance, onWhole.calibration.lightDistance);
    EXPECT_NEAR(onGrid.rms, onWhole.rms, 1e-9 * onWhole.rms);
}

// Where photometric stereo finds no normal (a black background), the grid estimated before
// any normal is known is laid again for the share that has one: about as many pixels as
// asked, each with the whole map's normal, and the very grid a search takes from them.
TEST(ExtendedModel, GridNormalsFollowTheShareOfPixelsWithANormal) {
    testing::TemporaryFolder folder;
    auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    spec.coefficients = [](int x, int y, int c, double* k) {
        glossy(x, y, c, k);
        if (x < 48) {                                         // three quarters of the image black
            std::fill_n(k, proto::coefficientCount(3), 0.0);  // domeSpec's M
        }
    };
    writeSyntheticCapture(folder / "train", spec);
    const capture::Capture capture = capture::openCapture(folder / "train");
    normals::PhotometricStereoOptions stereo;
    stereo.threads = 2;
    const normals::NormalMap whole = normals::estimateNormals(capture, stereo);
    const auto withNormal = std::count(whole.valid.begin(), whole.valid.end(), 1);
    ASSERT_GT(withNormal, 600);
    ASSERT_LT(withNormal, 900);
    constexpr int kWanted = 64;
    const normals::NormalMap grid =
        fit::heldOutGridNormals(capture, {}, spec.width, spec.height, kWanted, 2);
    const auto taken = std::count(grid.valid.begin(), grid.valid.end(), 1);
    EXPECT_GT(taken, kWanted / 2);
    EXPECT_LT(taken, kWanted * 9 / 4);
    for (std::size_t p = 0; p < grid.valid.size(); ++p) {
        if (grid.valid[p]) {
            ASSERT_TRUE(whole.valid[p]) << "pixel " << p;
            EXPECT_EQ(grid.xyz[p * 3], whole.xyz[p * 3]) << "pixel " << p;
        }
    }
    EXPECT_EQ(fit::heldOutGridPixels(grid, kWanted), grid.valid);
}

// A photograph exposed at 20% (a flash that misfired) among the lights the search holds out
// first: judged on that one fold, its error outweighs the geometry's; judged on every fold,
// the camera and the lights are still found.
TEST(ExtendedModel, CalibrationSurvivesAMisfiredExposure) {
    testing::TemporaryFolder folder;
    GeometrySearchCase c = geometrySearchCase(folder);
    capture::Capture& capture = c.capture;
    {
        const std::filesystem::path image = capture.images[7].file;
        const OIIO::ImageBuf dark = OIIO::ImageBufAlgo::mul(OIIO::ImageBuf(image.string()), 0.2f);
        ASSERT_TRUE(dark.write((folder / "misfired.exr").string()));
    }
    capture.images[7].file = folder / "misfired.exr";
    const fit::HeldOutSearchResult result = fit::searchHeldOut(capture, c.normals, c.options);
    EXPECT_NEAR(result.calibration.fieldOfViewDegrees, 40.0, 5.0);
    EXPECT_NEAR(result.calibration.lightDistance, 5.0, 1.0);
}

TEST(ExtendedModel, CalibratedFitPredictsHeldOutLightsOfTheSameRigBetter) {
    testing::TemporaryFolder folder;
    auto train = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    train.geometry = {40.0, 5.0, 0.0, {}};
    writeSyntheticCapture(folder / "train", train);
    auto test = domeSpec({20, 40, 60, 80}, 5, 18);
    test.geometry = train.geometry;
    writeSyntheticCapture(folder / "test", test);
    const auto [paper, extended] = heldOutPsnrsOfBothVariants(folder);
    EXPECT_GT(extended, paper + 6.0) << "paper " << paper << " dB, extended " << extended;

    model::ModelReader reader(folder / "extended.exr");
    EXPECT_EQ(reader.info().variant, "extended");
    EXPECT_NEAR(reader.info().calibration.fieldOfViewDegrees, 40.0, 5.0);
    EXPECT_NEAR(reader.info().calibration.lightDistance, 5.0, 1.0);
    model::ModelRows rows;
    reader.readRows(0, 1, rows);
    EXPECT_EQ(rows.transport.size(),
              static_cast<std::size_t>(train.width) * model::kTransportValues);
}

// 8-bit images that store radiance linearly, under a light file that cannot say so: decoded
// as sRGB, a Lambertian falloff looks like cos^2.2 and the BRDF extrapolates it badly to lights
// lower than the training ones. The response stage finds γ = 1 and the prediction recovers
// (measured: 36.2 dB decoded as sRGB, 44.9 dB calibrated; T's weaker ridge, chosen on
// held-out lights, hides part of the wrong curve in the sRGB fit).
TEST(ExtendedModel, ResponseCalibrationFindsLinearlyStoredImages) {
    testing::TemporaryFolder folder;
    auto train = domeSpec({40, 60, 80}, 12, 0);
    train.format = testing::SyntheticFormat::kPng8Linear;
    writeSyntheticCapture(folder / "train", train);
    auto test = domeSpec({25, 50, 70}, 5, 18);
    test.format = train.format;
    writeSyntheticCapture(folder / "test", test);
    const double srgb = heldOutPsnr(folder / "train", folder / "test", folder / "srgb.exr",
                                    fit::ModelVariant::kExtended, false);
    const double calibrated = heldOutPsnr(folder / "train", folder / "test",
                                          folder / "calibrated.exr", fit::ModelVariant::kExtended);
    EXPECT_EQ(model::ModelReader(folder / "srgb.exr").info().calibration.responseGamma, 0.0);
    EXPECT_EQ(model::ModelReader(folder / "calibrated.exr").info().calibration.responseGamma, 1.0);
    EXPECT_GT(calibrated, srgb + 8.0) << "sRGB " << srgb << " dB, calibrated " << calibrated;
}

// A manifest that states its encoding is trusted: the response stage does not run, and a
// model calibrated on a light-file capture predicts a stated capture under the stated curve.
TEST(ExtendedModel, AStatedEncodingIsNotCalibrated) {
    testing::TemporaryFolder folder;
    auto train = domeSpec({40, 60, 80}, 12, 0);
    train.format = testing::SyntheticFormat::kPng8Linear;
    train.manifest = true;
    writeSyntheticCapture(folder / "train", train);
    capture::Capture capture = capture::openCapture(folder / "train");
    capture.encoding = capture::ImageEncoding::kSrgb;
    fit::FitOptions options;
    options.harmonics = 3;
    options.lambda = 0.1;
    options.variant = fit::ModelVariant::kExtended;
    options.writePreview = false;
    EXPECT_EQ(fit::fitCapture(capture, options, folder / "m.exr").calibration.responseGamma, 0.0);
    capture::GeometryCalibration calibration;
    calibration.responseGamma = 1.0;
    EXPECT_EQ(
        capture::applyAcceptedCalibration(capture, calibration, train.width, train.height).encoding,
        capture::ImageEncoding::kSrgb);
    capture.encoding = capture::ImageEncoding::kAuto;
    const capture::Capture calibrated =
        capture::applyAcceptedCalibration(capture, calibration, train.width, train.height);
    EXPECT_EQ(calibrated.encoding, capture::ImageEncoding::kGamma);
    EXPECT_EQ(calibrated.gamma, 1.0);
}

// sRGB images keep their sRGB decoding: the response stage must not invent a curve.
TEST(ExtendedModel, ResponseCalibrationKeepsSrgbImages) {
    testing::TemporaryFolder folder;
    auto train = domeSpec({40, 60, 80}, 12, 0);
    train.format = testing::SyntheticFormat::kPng8Srgb;
    writeSyntheticCapture(folder / "train", train);
    fit::FitOptions options;
    options.harmonics = 3;
    options.lambda = 0.1;
    options.variant = fit::ModelVariant::kExtended;
    options.writePreview = false;
    const fit::FitReport report =
        fit::fitCapture(capture::openCapture(folder / "train"), options, folder / "m.exr");
    const double gamma = report.calibration.responseGamma;
    EXPECT_TRUE(gamma == 0.0 || gamma >= 2.0) << "chose γ " << gamma;
}

// A ridge to the right of the left half of the image casts a shadow there: lights from the
// +x side below its horizon (35°) are blocked, but for a little light from the sky.
double leftHalfShadow(int x, int width, const proto::Vec3d& light) {
    if (x >= width / 2) {
        return 1.0;
    }
    const double azimuth = std::atan2(light.y, light.x) * 180 / M_PI;
    const double elevation = std::asin(std::clamp(light.z, -1.0, 1.0)) * 180 / M_PI;
    return std::fabs(azimuth) < 60 && elevation < 35 ? 0.15 : 1.0;
}

// The glossy dome capture with that shadow.
testing::SyntheticCaptureSpec shadowedDomeSpec() {
    auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    const int width = spec.width;
    spec.transport = [width](int x, int, const proto::Vec3d& light) {
        return leftHalfShadow(x, width, light);
    };
    return spec;
}

TEST(ExtendedModel, LightTransportExplainsShadowsAndKeepsThemOutOfTheMaterial) {
    testing::TemporaryFolder folder;
    const auto train = shadowedDomeSpec();
    const int width = train.width;
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "train", train);
    auto test = domeSpec({20, 40, 60, 80}, 5, 18);
    test.transport = train.transport;
    writeSyntheticCapture(folder / "test", test);
    const auto [paper, extended] = heldOutPsnrsOfBothVariants(folder);
    EXPECT_GT(extended, paper + 1.0) << "paper " << paper << " dB, extended " << extended;

    // The transferable part: both models' BRDFs rendered without shadows, against the truth.
    auto brdfError = [&](const char* name) {
        model::ModelReader reader(folder / name);
        model::ModelRows rows;
        reader.readRows(0, train.height, rows);
        double squared = 0;
        int count = 0;
        for (const proto::Vec3d& light : testing::domeLights({25, 55}, 8, 10)) {
            for (int y = 0; y < train.height; ++y) {
                for (int x = 0; x < width / 2; ++x) {
                    const proto::Vec3d n = truth.normals[static_cast<std::size_t>(y) * width + x];
                    const auto a = proto::reflectionAngles(n, light, proto::Vec3d{0, 0, 1});
                    const double expected = proto::evaluateFourierBrdf(truth.at(x, y, 1, width), 3,
                                                                       a.cosThetaD, a.cosThetaS);
                    const double actual = proto::evaluateFourierBrdf(rows.coefficientsAt(y, x, 1),
                                                                     3, a.cosThetaD, a.cosThetaS);
                    squared += (expected - actual) * (expected - actual);
                    ++count;
                }
            }
        }
        return std::sqrt(squared / count);
    };
    const double paperMaterial = brdfError("paper.exr");
    const double extendedMaterial = brdfError("extended.exr");
    // Measured: 0.057 → 0.025, against 0.0035 for a fit of the same material unshadowed.
    EXPECT_LT(extendedMaterial, 0.6 * paperMaterial)
        << "material error: paper " << paperMaterial << ", extended " << extendedMaterial;
}

// The search's light-transport stage alone, at the glossy material's M and λ.
fit::HeldOutSearchOptions transportSearch() {
    fit::HeldOutSearchOptions search;
    search.calibrateGeometry = false;
    search.selectRegularization = false;
    search.selectTransportRidge = true;
    search.harmonics = 3;
    search.lambda = 0.1;
    search.threads = 2;
    return search;
}

// A synthetic capture written to `folder`, its true normals, and the search's validator over
// its whole picture.
struct ValidatedCapture {
    capture::Capture capture;
    normals::NormalMap normals;
    std::unique_ptr<fit::HeldOutValidator> validator;
    ValidatedCapture(const std::filesystem::path& folder, const testing::SyntheticCaptureSpec& spec)
        : normals(testing::trueNormalMap(writeSyntheticCapture(folder / "capture", spec),
                                         spec.width, spec.height)) {
        capture = capture::openCapture(folder / "capture");
        validator = std::make_unique<fit::HeldOutValidator>(capture, normals, 4096, 4, 2);
    }
};

// The extended fit at the glossy material's M and λ, the default ridge.
fit::ExtendedFitSettings glossySettings() {
    fit::ExtendedFitSettings settings;
    settings.harmonics = 3;
    settings.lambda = 0.1;
    return settings;
}

// The held-out search judges T's ridge by the extended fit itself: on shadowed texels the
// fit with T predicts the held-out lights better than the BRDF alone, and the report's choice
// is the best of its trials.
TEST(ExtendedModel, TransportRidgeIsChosenByTheHeldOutExtendedFit) {
    testing::TemporaryFolder folder;
    const auto spec = shadowedDomeSpec();
    const ValidatedCapture validated(folder.path(), spec);
    const capture::Capture& capture = validated.capture;
    const normals::NormalMap& normals = validated.normals;
    const double plain = validated.validator->score(capture::GeometryCalibration{}, 3, 0.1);
    const double withTransport =
        validated.validator->scoreWithTransport(capture::GeometryCalibration{}, glossySettings())
            .pooled;
    // Measured: 17.9 → 13.9 levels with the default ridge.
    EXPECT_LT(withTransport, 0.85 * plain) << "plain " << plain << ", with T " << withTransport;

    const fit::HeldOutSearchResult found = fit::searchHeldOut(capture, normals, transportSearch());
    ASSERT_EQ(found.transportTrials.size(), 5u);
    for (const fit::TransportRidgeTrial& trial : found.transportTrials) {
        EXPECT_GE(trial.rms, found.transportRms) << "ridge " << trial.ridge;
    }
    // Measured: 12.3 levels, a weaker ridge than the default.
    EXPECT_LT(found.transportRms, 0.75 * found.rms);
    EXPECT_LT(found.transportRidge, fit::ExtendedFitSettings{}.transportRidge);
}

// The held-out RMS of the extended fit (the search's first fold, default ridge) on `spec`'s
// capture, without and with one of the fit's options, at the glossy material's M and λ.
std::pair<double, double> heldOutWithoutAndWith(const std::filesystem::path& folder,
                                                const testing::SyntheticCaptureSpec& spec,
                                                bool fit::ExtendedFitSettings::*option) {
    const ValidatedCapture validated(folder, spec);
    fit::ExtendedFitSettings settings = glossySettings();
    settings.*option = false;
    const double without =
        validated.validator->scoreWithTransport(capture::GeometryCalibration{}, settings).pooled;
    settings.*option = true;
    return {
        without,
        validated.validator->scoreWithTransport(capture::GeometryCalibration{}, settings).pooled};
}

// Light off a red neighbour: on the left half of the picture, lights from the +x side reach
// the texels redder (and less blue) the lower they are; the luminance stays. A grey T cannot
// draw that; T with a colour predicts the held-out lights' colour.
TEST(ExtendedModel, LightTransportTakesTheColourOfInterreflection) {
    testing::TemporaryFolder folder;
    auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    const int width = spec.width;
    spec.tint = [width](int x, int, int c, const proto::Vec3d& light) {
        if (x >= width / 2) {
            return 1.0;
        }
        const double red = 0.1 * (1 + light.x) * (1 - light.z);  // strongest low, from +x
        return c == 0 ? 1 + red : c == 2 ? 1 - 2 * red : 1 - red * (0.2126 - 2 * 0.0722) / 0.7152;
    };
    const auto [grey, colour] =
        heldOutWithoutAndWith(folder.path(), spec, &fit::ExtendedFitSettings::colourTransport);
    // Measured: 2.95 → 2.27 levels.
    EXPECT_LT(colour, 0.82 * grey) << "grey T " << grey << ", colour T " << colour;
}

// Ridges narrower than a pixel, along every fourth column of the picture (a relief's veins):
// their pixels see two facets, tilted 60° either way, and the light leaves one facet for the
// other faster than a texel's one normal and T under the search's ridge can follow. Their
// own lights ask for a weaker ridge; the flat texels keep the search's.
TEST(ExtendedModel, VeinTexelsTakeAWeakerTransportRidge) {
    testing::TemporaryFolder folder;
    auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    spec.transport = [](int x, int, const proto::Vec3d& light) {
        if (x % 4 != 0) {
            return 1.0;
        }
        const double s = std::sin(60 * M_PI / 180), c = std::cos(60 * M_PI / 180);
        const double facets = 0.5 * std::max(0.0, s * light.x + c * light.z) +
                              0.5 * std::max(0.0, -s * light.x + c * light.z);
        return facets / std::max(0.1, light.z);
    };
    const auto [searchRidge, texelRidges] =
        heldOutWithoutAndWith(folder.path(), spec, &fit::ExtendedFitSettings::texelRidges);
    // Measured: 9.69 → 8.46 levels (ridge 0.1 for every texel: 7.96).
    EXPECT_LT(texelRidges, 0.9 * searchRidge)
        << "the search's ridge " << searchRidge << ", texels' own " << texelRidges;
}

// A light between table entries takes its neighbours' intensity, the nearer one's more; a
// neighbour on its own ring counts before one above it.
TEST(ExtendedModel, LightIntensityTableInterpolatesAlongTheRing) {
    auto direction = [](double elevation, double azimuth) {
        const double e = elevation * M_PI / 180, a = azimuth * M_PI / 180;
        return proto::Vec3d{std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
    };
    const std::vector<capture::LightIntensity> table = {
        {direction(5, 0), 0.1}, {direction(5, 40), 0.3}, {direction(25, 20), 1.0}};
    EXPECT_EQ(capture::lightIntensityAt(table, direction(5, 40)),
              0.3);  // a calibrated light: its own
    EXPECT_NEAR(capture::lightIntensityAt(table, direction(5, 20)), 0.2,
                1e-3);  // midway on the ring
    EXPECT_NEAR(capture::lightIntensityAt(table, direction(5, 10)), 0.15, 1e-3);
    EXPECT_EQ(capture::lightIntensityAt({}, direction(5, 20)), 1.0);  // no table: as stated

    capture::Capture capture;
    capture.images.push_back({});
    capture.images[0].light = direction(5, 20);
    capture.images[0].intensity = 2.0;
    capture::GeometryCalibration calibration;
    calibration.lightIntensities = table;
    const capture::Capture calibrated =
        capture::applyGeometryCalibration(capture, calibration, 8, 8);
    EXPECT_NEAR(calibrated.images[0].intensity, 0.4, 1e-3);  // stated × calibrated
}

// A dome whose lowest lights a part of the rig blocks over a third of the azimuths: the
// held-out search finds those lights and no others, and the fit with them predicts its
// held-out lights better.
TEST(ExtendedModel, HeldOutSearchFindsBlockedLights) {
    testing::TemporaryFolder folder;
    auto spec = domeSpec({4, 8, 25, 45, 65, 85}, 12, 0);
    auto blocked = [](const proto::Vec3d& light) {
        const double azimuth = std::atan2(light.y, light.x) * 180 / M_PI;
        const double elevation = std::asin(std::clamp(light.z, -1.0, 1.0)) * 180 / M_PI;
        return elevation < 12 && azimuth > -70 && azimuth < 50;
    };
    spec.transport = [&](int, int, const proto::Vec3d& light) {
        return blocked(light) ? 0.05 : 1.0;
    };
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "capture", spec);
    const capture::Capture capture = capture::openCapture(folder / "capture");
    const normals::NormalMap normals = testing::trueNormalMap(truth, spec.width, spec.height);
    fit::HeldOutSearchOptions search = transportSearch();
    search.calibrateLightIntensities = true;
    search.compareClassicBases = true;
    const fit::HeldOutSearchResult found = fit::searchHeldOut(capture, normals, search);
    // Against the classic bases, each fold judged under the table calibrated without it: the
    // table of every light knows the held-out lights' own intensities.
    EXPECT_EQ(found.extendedEveryFold.imageMean, found.lightIntensityRms);
    // Measured over every fold: per-image held-out RMS 3.79 levels as stated, 1.88 with the
    // blocked lights calibrated on the other folds.
    EXPECT_LT(found.lightIntensityRms, 0.55 * found.lightIntensityStatedRms)
        << found.lightIntensityRms << " against " << found.lightIntensityStatedRms;
    const auto& table = found.calibration.lightIntensities;
    ASSERT_EQ(table.size(), capture.images.size());
    int blockedCount = 0;
    for (const capture::LightIntensity& entry : table) {
        if (blocked(entry.direction)) {
            ++blockedCount;
            EXPECT_LT(entry.intensity, 0.2) << "a blocked light at z " << entry.direction.z;
        } else {
            EXPECT_EQ(entry.intensity, 1.0) << "a free light at z " << entry.direction.z;
        }
    }
    EXPECT_EQ(blockedCount, 8);  // two rings × azimuths −60°, −30°, 0°, 30°
}

TEST(ExtendedModel, StatedGeometryIsNotRecalibrated) {
    testing::TemporaryFolder folder;
    testing::SyntheticCaptureSpec spec;  // a manifest: geometry as stated there
    spec.harmonics = 2;
    writeSyntheticCapture(folder / "capture", spec);
    capture::Capture capture = capture::openCapture(folder / "capture");
    capture.lightKind = capture::LightKind::kPoint;  // a rig that says where its lights are
    for (capture::CaptureImage& image : capture.images) {
        image.light = {image.light.x * 10, image.light.y * 10, image.light.z * 10};
    }
    capture.lightReferenceDistance = 10;
    EXPECT_FALSE(capture::acceptsGeometryCalibration(capture));
    fit::FitOptions options;
    options.harmonics = 2;
    options.variant = fit::ModelVariant::kExtended;
    options.writePreview = false;
    const fit::FitReport report = fit::fitCapture(capture, options, folder / "model.exr");
    EXPECT_TRUE(report.calibration.isIdentity());
    EXPECT_TRUE(model::ModelReader(folder / "model.exr").info().calibration.isIdentity());
}

// Photometric stereo is a Lambertian estimate: on a glossy material its normals lean towards
// the highlights. The extended fit's normal search refits them with the whole model.
TEST(ExtendedModel, NormalSearchRefinesPhotometricStereoNormals) {
    testing::TemporaryFolder folder;
    const auto spec = domeSpec({10, 30, 50, 70, 90}, 12, 0);
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "capture", spec);
    std::filesystem::remove(folder / "capture" / "normals.png");  // estimated, not given
    const capture::Capture capture = capture::openCapture(folder / "capture");
    const normals::NormalMap trueNormals = testing::trueNormalMap(truth, spec.width, spec.height);
    normals::PhotometricStereoOptions stereo;
    stereo.threads = 2;
    const normals::NormalMap estimated = normals::estimateNormals(capture, stereo);

    const fit::HeldOutValidator validator(capture, estimated, 4096, 4, 2);
    fit::ExtendedFitSettings settings;
    settings.harmonics = 3;
    settings.lambda = 0.1;
    const double asEstimated =
        validator.scoreWithTransport(capture::GeometryCalibration{}, settings).pooled;
    settings.normalSearchDegrees = 4;
    const double refined =
        validator.scoreWithTransport(capture::GeometryCalibration{}, settings).pooled;
    // Measured: 5.81 → 4.47 levels.
    EXPECT_LT(refined, 0.85 * asEstimated) << "held-out RMS " << asEstimated << " → " << refined;

    fit::FitOptions options;
    options.harmonics = 3;
    options.lambda = 0.1;
    options.variant = fit::ModelVariant::kExtended;
    options.writePreview = false;
    options.threads = 2;
    const fit::FitReport report = fit::fitCapture(capture, options, folder / "model.exr");
    EXPECT_EQ(report.normalSearchDegrees, 4.0);
    model::ModelReader reader(folder / "model.exr");
    model::ModelRows rows;
    reader.readRows(0, spec.height, rows);
    normals::NormalMap fitted;
    fitted.resize(spec.width, spec.height);
    for (std::size_t p = 0; p < rows.valid.size(); ++p) {
        fitted.valid[p] = rows.valid[p];
        std::copy_n(&rows.normal[p * 3], 3, &fitted.xyz[p * 3]);
    }
    const normals::AngularError before = normals::compareNormalMaps(estimated, trueNormals);
    const normals::AngularError after = normals::compareNormalMaps(fitted, trueNormals);
    std::printf("held-out RMS %.3f → %.3f levels; mean angular error %.2f° → %.2f°\n", asEstimated,
                refined, before.meanDegrees, after.meanDegrees);
    // Measured: 13.5° → 9.3° (the search moves a normal by at most 4 + 2 + 1°; 8.7° with a whole
    // fit per tilt).
    EXPECT_LT(after.meanDegrees, 0.7 * before.meanDegrees)
        << "mean angular error " << before.meanDegrees << "° → " << after.meanDegrees << "°";
}

// SynthRTI Multi/Object1/material2: texels of a dark background, a channel or two at a level
// of two. T's colour fit once let their quantization noise through into every channel
// (45.77 → 23.99 dB); it must keep the accuracy the grey T had.
TEST(ExtendedModelRealData, ColourTransportKeepsADarkBackgroundQuiet) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path set = data / "synthrti/Multi/Object1/material2";
    if (!std::filesystem::exists(set / "Dome")) {
        GTEST_SKIP() << set << " not found";
    }
    testing::TemporaryFolder folder;
    fit::FitOptions options;
    options.variant = fit::ModelVariant::kExtended;
    options.writePreview = false;
    options.threads = 2;
    fit::fitCapture(capture::openCapture(set / "Dome"), options, folder / "model.exr");
    const double psnr =
        eval::evaluateModel(folder / "model.exr", capture::openCapture(set / "Test"),
                            eval::EvaluationOptions{})
            .psnr;
    // Measured: 46.31 dB (`vpe fit --model extended`: 45.79; grey T 45.77; the faulty colour
    // fit 23.99).
    EXPECT_GT(psnr, 45.5);
}

}  // namespace
}  // namespace vpe
