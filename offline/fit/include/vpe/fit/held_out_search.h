// SPDX-License-Identifier: MIT
// Held-out selection of what a capture cannot state: the extended model picks the camera's
// response, field of view, the lights' distance, and the harmonics M and smoothness λ that let the
// Fourier BRDF predict the capture best. Only the capture's own training images are used:
// a grid of pixels is fitted on three quarters of the lights and scored on the held-out
// quarter (every quarter in turn for the camera and the rig), in the metric of `vpe eval`.
// A few global numbers cannot overfit thousands of pixels.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/geometry_calibration.h"
#include "vpe/fit/extended_chunk_fit.h"
#include "vpe/model/rti_basis.h"
#include "vpe/normals/normal_map.h"

namespace vpe::fit {

// Held-out RMS in 8-bit levels: pooled over every held-out sample, and the geometric mean
// of the held-out images' RMS (whose PSNR is the images' mean PSNR, vpe eval's figure).
struct HeldOutScore {
    double pooled = 0;
    double imageMean = 0;
};

// Which of the training lights a score predicts: the one fold (positions holdOutEvery − 1,
// 2·holdOutEvery − 1, …), or every light in turn, each fold fitted on the other three.
enum class HeldOutFolds { kOne, kEvery };

// Scores hypotheses on a fixed grid of pixels, decoded once.
class HeldOutValidator {
public:
    HeldOutValidator(const capture::Capture& capture, const normals::NormalMap& normals,
                     int samplePixels, int holdOutEvery, unsigned threads);
    ~HeldOutValidator();
    HeldOutValidator(const HeldOutValidator&) = delete;
    HeldOutValidator& operator=(const HeldOutValidator&) = delete;

    // Held-out RMS in 8-bit sRGB levels of a fit under this geometry, M and λ.
    double score(const capture::GeometryCalibration& calibration, int harmonics, double lambda,
                 HeldOutFolds folds = HeldOutFolds::kOne) const;
    // The same for the extended model's fit, light transport T included (settings give M, λ
    // and T's ridge).
    HeldOutScore scoreWithTransport(const capture::GeometryCalibration& calibration,
                                    const fit::ExtendedFitSettings& settings,
                                    HeldOutFolds folds = HeldOutFolds::kOne) const;
    // A classic RTI basis fitted as RTI tools fit it (least squares on the images' stored
    // values, no ridge; rti_band_fitter.h) and scored the same way: what the extended model
    // is measured against on the capture's own training lights.
    HeldOutScore scoreRtiBasis(const model::RtiBasis& basis, HeldOutFolds folds) const;
    // The same over every fold, fold k fitted and predicted under byFold[k] (one calibration
    // per fold, holdOutEvery of them): what each fold gives when something is calibrated on
    // the other folds' lights alone.
    HeldOutScore scoreWithTransportByFold(const std::vector<capture::GeometryCalibration>& byFold,
                                          const fit::ExtendedFitSettings& settings) const;
    // Each light's gain under that extended fit: the factor Σ ŷ y / Σ ŷ² by which the grid's
    // observations y exceed the model's predictions ŷ, for the lights the fit used (all
    // lights when heldOutFold < 0, else all but that fold's: positions heldOutFold,
    // heldOutFold + holdOutEvery, …); 0 for the others.
    std::vector<double> lightGains(const capture::GeometryCalibration& calibration,
                                   const fit::ExtendedFitSettings& settings, int heldOutFold) const;

    struct Samples;  // the decoded pixel grid (defined in the .cpp)
    // The grid's normals as the extended fit's normal search refined them on one training set
    // (the lights outside heldOutFold; all for −1) under one rig (field of view, light
    // distance, response) and T's ridge: refined by the first extended fit of that set,
    // reused by the hypotheses after it (refinedNormals in the .cpp).
    struct RefinedNormals {
        int heldOutFold = 0;
        capture::GeometryCalibration rig;
        double transportRidge = 0;
        bool filled = false;
        std::vector<float> xyz;  // per grid sample, 3 each
    };

private:
    RefinedNormals& refinedNormals(const capture::GeometryCalibration& calibration,
                                   double transportRidge, int heldOutFold) const;

    const capture::Capture& capture_;
    const normals::NormalMap& normals_;
    int holdOutEvery_;
    unsigned threads_;
    std::unique_ptr<Samples> samples_;
    mutable std::vector<std::unique_ptr<RefinedNormals>> refinedNormals_;
};

struct HeldOutSearchOptions {
    // The camera response (8-bit images whose encoding is unstated): a power law γ against
    // the stated sRGB. Scored in the images' stored values, so the candidates compare.
    bool calibrateResponse = false;
    bool calibrateGeometry = true;
    bool selectRegularization = true;
    int harmonics = 10;  // used as given when not selecting
    double lambda = 3.14;
    unsigned threads = 1;
    // The extended model's light transport T: how strongly its per-texel fit is pulled
    // towards T ≡ 1, judged last, by the extended fit itself under what was chosen above.
    bool selectTransportRidge = false;
    // The extended fit's normal search (ExtendedFitSettings::normalSearchDegrees) the ridge is
    // judged under: the final fit's own.
    double normalSearchDegrees = 0;
    // Lights that a part of the rig blocks (capture::GeometryCalibration::lightIntensities: those
    // reaching the object at under 90% of the median light keep their own intensity), judged
    // after T's ridge by the extended fit: kept when they predict the held-out lights better.
    bool calibrateLightIntensities = false;
    // Last, the extended model as chosen and the classic RTI bases (PTM-6, HSH-9, HSH-16),
    // each over every fold of the training lights: whether the extended model predicts this
    // capture's own lights better than what RTI tools would fit (with selectTransportRidge).
    bool compareClassicBases = false;
    // The grid's size. Every stage's time grows with it; a score over 1,024 pixels is over
    // some 30,000 held-out values a fold. 1,024 against 4,096: on realrti-dev the same
    // response, M, λ and T's ridge on every item (r0), the rig's geometry a few degrees apart
    // on three; the extended mean −0.01, 0.00 and +0.16 dB on the three rotations, every item
    // still above its HSH-16; SynthRTI 33.55 → 33.60 dB. The search took a third of the time.
    int samplePixels = 1024;
    int holdOutEvery = 4;
};

struct TransportRidgeTrial {
    double ridge = 0;
    double rms = 0;
};

// A classic RTI basis's held-out score on the training lights (compareClassicBases).
struct ClassicBasisScore {
    std::string basis;  // "hsh16"
    HeldOutScore score;
};

// Where a search's time went: one stage's name and its seconds.
struct SearchStageTime {
    std::string stage;
    double seconds = 0;
};

struct HeldOutTrial {
    capture::GeometryCalibration calibration;
    int harmonics = 0;
    double lambda = 0;
    HeldOutFolds folds = HeldOutFolds::kOne;
    double rms = 0;  // held-out RMS, 8-bit sRGB levels
};

struct HeldOutSearchResult {
    capture::GeometryCalibration calibration;
    int harmonics = 0;
    double lambda = 0;
    double rms = 0;          // of the choice, over the folds that judged the camera and rig
    double baselineRms = 0;  // stated geometry with the given M and λ, the same way
    std::vector<HeldOutTrial> trials;
    // Only with selectTransportRidge (else the fit's default and no trials).
    double transportRidge = fit::ExtendedFitSettings{}.transportRidge;
    double transportRms = 0;  // held-out RMS of the extended fit with that ridge
    std::vector<TransportRidgeTrial> transportTrials;
    // Only with calibrateLightIntensities: the per-image held-out RMS (HeldOutScore::imageMean)
    // over every fold of the extended fit with the intensities calibrated on the other folds'
    // lights, adopted when below lightIntensityStatedRms, the same with the lights as stated.
    double lightIntensityRms = 0;
    double lightIntensityStatedRms = 0;
    // Only with compareClassicBases: the extended model as chosen and the classic bases, each
    // over every fold (the extended one's scores 0 when not compared).
    HeldOutScore extendedEveryFold;
    std::vector<ClassicBasisScore> classicBases;
    // The stages run, in order, with their seconds.
    std::vector<SearchStageTime> stageSeconds;
};

HeldOutSearchResult searchHeldOut(const capture::Capture& capture,
                                  const normals::NormalMap& normals,
                                  const HeldOutSearchOptions& options);

// The pixels the search's grid takes (W × H, 1 where taken): about `samplePixels` of those
// with a normal, on a square lattice. A normal map holding only these pixels gives the same
// grid, so a search can run on normals estimated there alone.
std::vector<std::uint8_t> heldOutGridPixels(const normals::NormalMap& normals, int samplePixels);
// The same grid before any normal is known: of the `candidates` (W × H, nonzero where a pixel
// may have one), as if `validShare` of them had a normal.
std::vector<std::uint8_t> heldOutGridPixels(const std::vector<std::uint8_t>& candidates, int width,
                                            int height, double validShare, int samplePixels);
// Photometric stereo on that grid alone, of the pixels in `mask` (W × H; empty: all): what a
// search needs of a normal map it has not estimated yet.
normals::NormalMap heldOutGridNormals(const capture::Capture& capture,
                                      const std::vector<std::uint8_t>& mask, int width, int height,
                                      int samplePixels, unsigned threads);

}  // namespace vpe::fit
