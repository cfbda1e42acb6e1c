// SPDX-License-Identifier: MIT
// Alternating fit of BRDF and light transport.
#include "vpe/fit/extended_chunk_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <utility>

#include <Eigen/Dense>

#include "vpe/fit/extended_lane_kernels.h"
#include "vpe/proto/detail_normal.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/luminance.h"

namespace vpe::fit {

namespace {

using proto::kLuminance709;

double luminance(double r, double g, double b) {
    return proto::luminance709(r, g, b);
}
double luminance(float r, float g, float b) {
    return luminance(static_cast<double>(r), static_cast<double>(g), static_cast<double>(b));
}

using TransportMatrix = Eigen::Matrix<double, model::kTransportTerms, model::kTransportTerms>;
constexpr int kTransportPairs = ExtendedLightTable::kTransportPairs;
using TransportVector = Eigen::Matrix<double, model::kTransportTerms, 1>;

// Calls visit(row, column, k) for each distinct entry of a symmetric kTransportTerms² matrix,
// k its index in the packed layout (the upper triangle, row by row).
template <typename Visit>
void forEachTransportPair(Visit visit) {
    for (int row = 0, k = 0; row < model::kTransportTerms; ++row) {
        for (int column = row; column < model::kTransportTerms; ++column, ++k) {
            visit(row, column, k);
        }
    }
}

// The normal equations of Σ w (y − T(l) P)² over a lane's samples, as one lane's matrix: where
// the lanes' Cholesky (solveTransportLanes) fails. Built from the sums of every lane and
// channel of a chunk (ExtendedChunkFit::buildTransportEquations).
struct TransportEquations {
    TransportMatrix a = TransportMatrix::Zero();
    TransportVector b = TransportVector::Zero();
    double meanWeight = 0;  // of w P², the scale the ridges are relative to

    // min Σ w (y − T P)² + ridge · meanWeight · ‖t − prior‖² by LDLT, for a lane whose
    // Cholesky failed (no ridge, degenerate lights); not finite when this fails too.
    TransportVector solveByLdlt(double ridge, const TransportVector& prior) const {
        TransportMatrix regularized = a;
        regularized.diagonal().array() += ridge * meanWeight;
        return regularized.ldlt().solve(b + ridge * meanWeight * prior);
    }
};

}  // namespace

ExtendedLightTable::ExtendedLightTable(const capture::Capture& capture) {
    transportBasis.reserve(capture.images.size());
    transportOuter.reserve(capture.images.size());
    for (const capture::CaptureImage& image : capture.images) {
        std::array<double, model::kTransportTerms> basis;
        model::lightTransportBasis(model::transportDirection(capture, image), basis.data());
        transportBasis.push_back(basis);
        std::array<double, kTransportPairs> outer;
        forEachTransportPair([&](int row, int column, int k) {
            outer[static_cast<std::size_t>(k)] =
                basis[static_cast<std::size_t>(row)] * basis[static_cast<std::size_t>(column)];
        });
        transportOuter.push_back(outer);
    }
}

namespace {

// The alternating fit of one chunk of kLanes texels (docs/extended-model.md, "How it is
// fitted", step 2): f by least squares, f again as an upper envelope (shadow weights), then T
// given f and f given T, twice. Its buffers hold every sample of every lane and are kept from
// one chunk to the next, so each thread has one (fitChunkExtended).
class ExtendedChunkFit {
public:
    void fit(const capture::Capture& capture, const ExtendedLightTable& table,
             const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
             const KernelLightSet& lights, const capture::SampleBand& band, int row, int x0,
             const ExtendedFitSettings& settings, ExtendedChunkSolution& out,
             const double* laneRidges);
    // After fit(): the same chunk's fit again under other normals (`geometry`'s), the samples
    // as fit() read them; only each sample's angles change.
    void refit(const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
               const KernelLightSet& lights, ExtendedChunkSolution& out, const double* laneRidges);
    // After fit(): keeps that fit's T per sample as the centre a normal search tries its
    // tilts around.
    void rememberCentre();
    // A tilt's trial: from the centre's fit (`centre`: its f, T and ridges), T fitted once to
    // the centre's f as `candidate`'s normals shade it, then f once under that T, with the
    // centre's shadow weights and censoring; into `out` with its training error. One T fit and
    // one BRDF fit where a whole fit takes two and four. T's colour is fitted again only with
    // `refitColour`; otherwise the tilt carries the centre's (carryCentreTint).
    void tryTilt(const ChunkGeometry& candidate, const KernelLightSet& lights,
                 const ExtendedChunkSolution& centre, ExtendedChunkSolution& out, bool refitColour);

private:
    // Index of sample s, lane `lane` in the per-sample buffers; of its channel c in values_.
    static std::size_t at(int s, int lane) { return static_cast<std::size_t>(s) * kLanes + lane; }
    static std::size_t valueAt(int s, int c, int lane) {
        return (static_cast<std::size_t>(s) * 3 + c) * kLanes + lane;
    }
    void readObservations(const capture::Capture& capture, const ChunkGeometry& geometry,
                          const capture::SampleBand& band, int row, int x0);
    // cosθd and cosθs of every sample and lane under `geometry`'s normals.
    void shade(const ChunkGeometry& geometry);
    // T ≡ 1 and nothing censored: where every fit of a chunk starts.
    void resetTransport();
    // The alternation itself (fit's steps after reading the samples).
    void alternate(const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                   const KernelLightSet& lights, ExtendedChunkSolution& out,
                   const double* laneRidges);
    void setGreyTransport(int lane, const double* coefficients);
    double observedLuminance(int s, int lane) const;
    // Whether sample index i (at()) counts in T's fit and the shadow scale: it has a weight and
    // is not censored.
    bool usable(std::size_t i) const { return weights_[i] > 0 && !censored_[i]; }
    LaneSamples laneSamples() const {
        return {samples_, cosD_.data(), cosS_.data(), irradiance_.data()};
    }
    void predictLanes();
    void chooseTexelRidges(const bool (&lanes)[kLanes], double (&ridges)[kLanes]);
    void buildTransportEquations(const bool (&lanes)[kLanes], bool colour);
    // T's coefficients of every lane of a chunk: [term][lane].
    using LaneTransport = std::array<double, model::kTransportTerms * kLanes>;
    static std::size_t transportIndex(int term, int lane) {
        return static_cast<std::size_t>(term) * kLanes + static_cast<std::size_t>(lane);
    }
    // A lane's equations of `channel` (0 luminance, 1 + c colour) as a matrix, from the sums
    // buildTransportEquations made: where the lanes' Cholesky fails.
    TransportEquations transportEquations(int lane, int channel) const;
    // Channel `channel`'s ridge solves of the `lanes`, every lane at once (solveTransportLanes,
    // LDLT where it fails); `finite` says which lanes have a solution.
    void solveTransport(int channel, const bool (&lanes)[kLanes], const double (&ridges)[kLanes],
                        const LaneTransport& prior, LaneTransport& t, bool (&finite)[kLanes]) const;
    // T of every sample of the `lanes` into out[s · stride + lane], for each (out, stride)
    // given.
    void sampleLanes(const LaneTransport& t, const bool (&lanes)[kLanes],
                     std::initializer_list<std::pair<float*, std::size_t>> outputs);
    void fitTransport(const bool (&active)[kLanes], bool (&fitted)[kLanes]);
    void carryCentreTint(const bool (&lanes)[kLanes], const ExtendedChunkSolution& centre);
    void fitColourTransport(const bool (&lanes)[kLanes]);
    void updateShadowWeights(int lane);
    void fitBrdf(const ChunkGeometry& geometry, const KernelLightSet& lights,
                 NormalEquationSums& sums);
    void keepPlainFit(const ChunkSolution& firstRound);
    void trainingErrors();

    // The chunk under way (set by fit).
    const ExtendedLightTable* table_ = nullptr;
    const ExtendedFitSettings* settings_ = nullptr;
    ExtendedChunkSolution* out_ = nullptr;
    const double* laneRidges_ = nullptr;  // T's ridges as given, or chosen per texel
    int samples_ = 0;
    std::size_t laneBlock_ = 0;
    double identity_[model::kTransportTerms] = {};
    LaneTransport identityLanes_ = {};  // T ≡ 1 for every lane: T's prior
    // The luminance T fit's mean weight per lane; 0 while the lane has no fitted T.
    double luminanceWeight_[kLanes] = {};

    // Per sample and lane: raw observations, usable weight, saturation, model geometry.
    std::vector<float> values_, weights_, scaled_, scaledWeights_, transport_, channelTransport_;
    std::vector<std::uint8_t> saturated_, censored_;
    std::vector<double> cosD_, cosS_, irradiance_;
    // Each sample's direction to its light, per axis, [sample][lane] (the tilts reuse them).
    std::vector<double> lightX_, lightY_, lightZ_;
    // The centre of a normal search (rememberCentre): its T per sample, and per lane the mean
    // weight of its luminance T fit.
    std::vector<float> centreTransport_, centreChannelTransport_;
    double centreLuminanceWeight_[kLanes] = {};
    std::vector<float> robust_;         // shadow down-weighting of the BRDF fit
    std::vector<double> predicted_;     // the BRDF's luminance prediction, per sample and lane
    std::vector<double> predictedRgb_;  // per sample, channel and lane (predictLanes)
    std::vector<double> magnitudes_;
    // The luminance samples of the texels' ridge choice, [sample][lane] (chooseTexelRidges).
    std::vector<double> pressWeights_, pressObserved_;
    // T's normal equations of every lane (buildTransportEquations): the mean weight of
    // luminance, then R, G, B ([channel][lane]; 0 where not built), and the products they are
    // made by.
    double meanWeights_[1 + model::kTransportChannels][kLanes] = {};
    std::vector<float> sampled_;                        // sampleLanes' T of every sample and lane
    std::vector<double> sampleWeights_, sampleRights_;  // [sample][channel][lane]
    std::vector<double> pairSums_, rightSums_;          // [channel][pair or term][lane]
};

void ExtendedChunkFit::fit(const capture::Capture& capture, const ExtendedLightTable& table,
                           const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                           const KernelLightSet& lights, const capture::SampleBand& band, int row,
                           int x0, const ExtendedFitSettings& settings, ExtendedChunkSolution& out,
                           const double* laneRidges) {
    table_ = &table;
    settings_ = &settings;
    samples_ = lights.count;
    laneBlock_ = static_cast<std::size_t>(samples_) * kLanes;
    readObservations(capture, geometry, band, row, x0);
    alternate(geometry, laneValid, lights, out, laneRidges);
}

void ExtendedChunkFit::refit(const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                             const KernelLightSet& lights, ExtendedChunkSolution& out,
                             const double* laneRidges) {
    resetTransport();
    shade(geometry);
    alternate(geometry, laneValid, lights, out, laneRidges);
}

void ExtendedChunkFit::alternate(const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                                 const KernelLightSet& lights, ExtendedChunkSolution& out,
                                 const double* laneRidges) {
    const ExtendedFitSettings& settings = *settings_;
    out_ = &out;
    laneRidges_ = laneRidges;
    model::identityTransport(identity_);
    for (int lane = 0; lane < kLanes; ++lane) {
        for (int k = 0; k < model::kTransportTerms; ++k) {
            identityLanes_[transportIndex(k, lane)] = identity_[k];
        }
        setGreyTransport(lane, identity_);
        luminanceWeight_[lane] = 0;
        out.transportRidge[lane] = laneRidges ? laneRidges[lane] : settings.transportRidge;
    }
    robust_.assign(laneBlock_, 1.0f);
    predicted_.assign(laneBlock_, 0.0);
    magnitudes_.clear();

    auto sums = std::make_unique<NormalEquationSums>();
    auto firstRound = std::make_unique<ChunkSolution>();
    const int rounds = std::max(1, settings.rounds);
    for (int round = 0;; ++round) {
        fitBrdf(geometry, lights, *sums);
        if (round == 0) {
            *firstRound = out.brdf;
        }
        if (round + 1 >= rounds) {
            break;
        }
        // Round 0's BRDF still carries the shadows, so T waits for the reweighted fit.
        bool active[kLanes];
        for (int lane = 0; lane < kLanes; ++lane) {
            active[lane] = laneValid[lane] && out.brdf.valid[lane];
        }
        predictLanes();
        if (round >= 1) {
            buildTransportEquations(active, settings.colourTransport);
            bool fitted[kLanes];
            fitTransport(active, fitted);
            if (settings.colourTransport) {
                bool colour[kLanes];
                for (int lane = 0; lane < kLanes; ++lane) {
                    colour[lane] = active[lane] && luminanceWeight_[lane] > 0;
                }
                fitColourTransport(colour);
            }
        }
        for (int lane = 0; lane < kLanes; ++lane) {
            if (active[lane]) {
                updateShadowWeights(lane);
            }
        }
    }
    keepPlainFit(*firstRound);
    trainingErrors();
}

void ExtendedChunkFit::readObservations(const capture::Capture& capture,
                                        const ChunkGeometry& geometry,
                                        const capture::SampleBand& band, int row, int x0) {
    values_.resize(laneBlock_ * 3);
    scaled_.resize(laneBlock_ * 3);
    weights_.resize(laneBlock_);
    scaledWeights_.resize(laneBlock_);
    resetTransport();
    saturated_.resize(laneBlock_);
    cosD_.resize(laneBlock_);
    cosS_.resize(laneBlock_);
    irradiance_.resize(laneBlock_);
    predictedRgb_.resize(laneBlock_ * 3);
    lightX_.resize(laneBlock_);
    lightY_.resize(laneBlock_);
    lightZ_.resize(laneBlock_);
    for (int s = 0; s < samples_; ++s) {
        const capture::CaptureImage& image = capture.images[static_cast<std::size_t>(s)];
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t i = at(s, lane);
            weights_[i] = band.weight(s, row, x0 + lane);
            saturated_[i] = band.isSaturated(s, row, x0 + lane) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                values_[valueAt(s, c, lane)] = band.value(s, c, row, x0 + lane);
            }
            const proto::Vec3d p{geometry.position[0][lane], geometry.position[1][lane],
                                 geometry.position[2][lane]};
            const capture::IncidentLight light = capture::incidentLight(capture, image, p);
            irradiance_[i] = light.irradiance;
            lightX_[i] = light.direction.x;
            lightY_[i] = light.direction.y;
            lightZ_[i] = light.direction.z;
        }
    }
    shade(geometry);
}

void ExtendedChunkFit::resetTransport() {
    transport_.assign(laneBlock_, 1.0f);
    channelTransport_.assign(laneBlock_ * 3, 1.0f);  // per sample, channel and lane, as values
    censored_.assign(laneBlock_, 0);
}

// The angles by proto's own definition (reflection_geometry.h), which the renderer shares.
void ExtendedChunkFit::shade(const ChunkGeometry& geometry) {
    for (int lane = 0; lane < kLanes; ++lane) {
        const proto::Vec3d n{geometry.normal[0][lane], geometry.normal[1][lane],
                             geometry.normal[2][lane]};
        const proto::Vec3d v{geometry.view[0][lane], geometry.view[1][lane],
                             geometry.view[2][lane]};
        for (int s = 0; s < samples_; ++s) {
            const std::size_t i = at(s, lane);
            const auto angles =
                proto::reflectionAngles(n, proto::Vec3d{lightX_[i], lightY_[i], lightZ_[i]}, v);
            cosD_[i] = angles.cosThetaD;
            cosS_[i] = angles.cosThetaS;
        }
    }
}

void ExtendedChunkFit::setGreyTransport(int lane, const double* coefficients) {
    for (int c = 0; c < model::kTransportChannels; ++c) {
        for (int k = 0; k < model::kTransportTerms; ++k) {
            out_->transport[lane][c * model::kTransportTerms + k] =
                static_cast<float>(coefficients[k]);
        }
    }
}

double ExtendedChunkFit::observedLuminance(int s, int lane) const {
    const std::size_t base = static_cast<std::size_t>(s) * 3 * kLanes + lane;
    return luminance(values_[base], values_[base + kLanes], values_[base + 2 * kLanes]);
}

// The BRDF's prediction of every sample of every lane, in image units: per channel (for the
// colour T fit that follows) and its luminance. A lane without a fit yet predicts values nobody
// reads.
void ExtendedChunkFit::predictLanes() {
    predictEveryLane(out_->brdf, settings_->harmonics, laneSamples(), predictedRgb_.data(),
                     predicted_.data());
}

// Each texel's T ridge, relative to its mean sample weight: the search's, or a weaker one
// (0.3, 0.1, 0.03 or 0.01 of it, none below the weakest the search tries) where the texel's own
// lights call for it. They call when the ridge fit's leave-one-light-out error (PRESS, in
// closed form: residual / (1 − leverage); transportPressLanes) falls by at least a fifth,
// about one standard error of a PRESS over some forty lights; on flat texels a weaker ridge
// only fits noise. On realrti-dev item7 (clay relief) the veins are such texels: the light
// falls off their flanks faster than the search's ridge lets T draw (+0.3 dB on held-out
// lights). Every lane at once under the predictions of predictLanes: a Cholesky factor per
// candidate and a forward substitution per sample, where each lane's eigendecomposition,
// its samples projected on the eigenvectors, and their PRESS one lane after the other were a
// fifth of the extended fit's time.
void ExtendedChunkFit::chooseTexelRidges(const bool (&lanes)[kLanes], double (&ridges)[kLanes]) {
    constexpr double kWeakest = 0.01;
    constexpr double kRequiredGain = 0.8;
    pressWeights_.assign(laneBlock_, 0.0);
    pressObserved_.assign(laneBlock_, 0.0);
    for (int s = 0; s < samples_; ++s) {
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t i = at(s, lane);
            if (lanes[lane] && usable(i)) {
                pressWeights_[i] = static_cast<double>(weights_[i]);
                pressObserved_[i] = observedLuminance(s, lane);
            }
        }
    }
    const LanePressSamples samples{samples_, pressWeights_.data(), predicted_.data(),
                                   pressObserved_.data()};
    const double ridge = settings_->transportRidge;
    double best[kLanes] = {};
    for (double factor : {1.0, 0.3, 0.1, 0.03, 0.01}) {
        const double candidate = ridge * factor;
        if (factor < 1 && candidate < kWeakest * (1 - 1e-9)) {
            break;
        }
        double pull[kLanes];
        for (int lane = 0; lane < kLanes; ++lane) {
            pull[lane] = lanes[lane] ? candidate * meanWeights_[0][lane] : 1.0;
        }
        double press[kLanes];
        bool valid[kLanes];
        transportPressLanes(*table_, pairSums_.data(), rightSums_.data(), pull,
                            identityLanes_.data(), samples, press, valid);
        for (int lane = 0; lane < kLanes; ++lane) {
            if (!lanes[lane] || !valid[lane]) {
                continue;
            }
            const double score = factor < 1 ? press[lane] / kRequiredGain : press[lane];
            if (factor == 1 || score < best[lane]) {
                best[lane] = score;
                ridges[lane] = candidate;
            }
        }
    }
}

// T's normal equations of the `lanes`, from the predictions of predictLanes: luminance and,
// with `colour`, each colour channel, over each lane's usable samples (the others weigh 0).
void ExtendedChunkFit::buildTransportEquations(const bool (&lanes)[kLanes], bool colour) {
    const int channels = colour ? 1 + model::kTransportChannels : 1;
    const std::size_t perSample = static_cast<std::size_t>(channels) * kLanes;
    sampleWeights_.resize(static_cast<std::size_t>(samples_) * perSample);  // all written below
    sampleRights_.resize(sampleWeights_.size());
    std::fill_n(&meanWeights_[0][0], (1 + model::kTransportChannels) * kLanes, 0.0);
    // Sample by sample with the lanes innermost (each lane's sums in the same order as a lane
    // alone), so that the loop vectorizes.
    double weightSums[1 + model::kTransportChannels][kLanes] = {};
    int used[kLanes] = {};  // the same samples count in every channel
    for (int s = 0; s < samples_; ++s) {
        bool use[kLanes];
        for (int lane = 0; lane < kLanes; ++lane) {
            use[lane] = lanes[lane] && usable(at(s, lane));
            used[lane] += use[lane] ? 1 : 0;
        }
        for (int channel = 0; channel < channels; ++channel) {
            const std::size_t u0 = static_cast<std::size_t>(s) * perSample +
                                   static_cast<std::size_t>(channel) * kLanes;
            const double* __restrict predicted =
                channel == 0 ? &predicted_[at(s, 0)] : &predictedRgb_[valueAt(s, channel - 1, 0)];
            const float* __restrict weights = &weights_[at(s, 0)];
            double* __restrict sampleWeights = &sampleWeights_[u0];
            double* __restrict sampleRights = &sampleRights_[u0];
            double observed[kLanes];
            for (int lane = 0; lane < kLanes; ++lane) {
                observed[lane] = channel == 0
                                     ? observedLuminance(s, lane)
                                     : static_cast<double>(values_[valueAt(s, channel - 1, lane)]);
            }
            // Computed for every lane and kept where used (+0 elsewhere, as assign left it):
            // written so, the loop vectorizes.
            for (int lane = 0; lane < kLanes; ++lane) {
                const double wp = static_cast<double>(weights[lane]) * predicted[lane];
                const double square = wp * predicted[lane];
                sampleWeights[lane] = use[lane] ? std::max(square, 0.0) : 0.0;
                sampleRights[lane] = use[lane] ? wp * observed[lane] : 0.0;
                weightSums[channel][lane] += use[lane] ? square : 0.0;
            }
        }
    }
    for (int channel = 0; channel < channels; ++channel) {
        for (int lane = 0; lane < kLanes; ++lane) {
            meanWeights_[channel][lane] =
                lanes[lane] && used[lane] > 0 ? weightSums[channel][lane] / used[lane] : 0.0;
        }
    }
    pairSums_.resize(static_cast<std::size_t>(channels) * kTransportPairs * kLanes);
    rightSums_.resize(static_cast<std::size_t>(channels) * model::kTransportTerms * kLanes);
    sumTransportEquations(*table_, samples_, channels, sampleWeights_.data(), sampleRights_.data(),
                          pairSums_.data(), rightSums_.data());
}

TransportEquations ExtendedChunkFit::transportEquations(int lane, int channel) const {
    TransportEquations equations;
    // Entry `entry` of this lane's and channel's sums.
    const auto sum = [&](const std::vector<double>& sums, int entries, int entry) {
        return sums[static_cast<std::size_t>(channel * entries + entry) * kLanes +
                    static_cast<std::size_t>(lane)];
    };
    forEachTransportPair([&](int row, int column, int k) {
        equations.a(row, column) = sum(pairSums_, kTransportPairs, k);
        equations.a(column, row) = sum(pairSums_, kTransportPairs, k);
    });
    for (int t = 0; t < model::kTransportTerms; ++t) {
        equations.b[t] = sum(rightSums_, model::kTransportTerms, t);
    }
    equations.meanWeight = meanWeights_[channel][lane];
    return equations;
}

void ExtendedChunkFit::solveTransport(int channel, const bool (&lanes)[kLanes],
                                      const double (&ridges)[kLanes], const LaneTransport& prior,
                                      LaneTransport& t, bool (&finite)[kLanes]) const {
    double pull[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) {
        pull[lane] = lanes[lane] ? ridges[lane] * meanWeights_[channel][lane] : 1.0;
    }
    bool solved[kLanes];
    solveTransportLanes(
        &pairSums_[static_cast<std::size_t>(channel) * kTransportPairs * kLanes],
        &rightSums_[static_cast<std::size_t>(channel) * model::kTransportTerms * kLanes], pull,
        prior.data(), t.data(), solved);
    for (int lane = 0; lane < kLanes; ++lane) {
        finite[lane] = false;
        if (!lanes[lane]) {
            continue;
        }
        if (!solved[lane]) {
            TransportVector right;
            for (int k = 0; k < model::kTransportTerms; ++k) {
                right[k] = prior[transportIndex(k, lane)];
            }
            const TransportVector x =
                transportEquations(lane, channel).solveByLdlt(ridges[lane], right);
            for (int k = 0; k < model::kTransportTerms; ++k) {
                t[transportIndex(k, lane)] = x[k];
            }
        }
        finite[lane] = true;
        for (int k = 0; k < model::kTransportTerms; ++k) {
            finite[lane] = finite[lane] && std::isfinite(t[transportIndex(k, lane)]);
        }
    }
}

void ExtendedChunkFit::sampleLanes(const LaneTransport& t, const bool (&lanes)[kLanes],
                                   std::initializer_list<std::pair<float*, std::size_t>> outputs) {
    sampled_.resize(laneBlock_);
    sampleTransportLanes(*table_, t.data(), samples_, sampled_.data());
    for (const auto& [out, stride] : outputs) {
        for (int s = 0; s < samples_; ++s) {
            float* row = out + static_cast<std::size_t>(s) * stride;
            const float* sampled = &sampled_[at(s, 0)];
            for (int lane = 0; lane < kLanes; ++lane) {
                row[lane] = lanes[lane] ? sampled[lane] : row[lane];  // a blend: vectorizes
            }
        }
    }
}

// T given f, on luminance: min Σ w (L − T(l) P)² + ρ ‖t − t₁‖², ρ the texel's own
// (chooseTexelRidges). Every channel takes it.
void ExtendedChunkFit::fitTransport(const bool (&active)[kLanes], bool (&fitted)[kLanes]) {
    bool lanes[kLanes];
    double ridges[kLanes] = {};
    for (int lane = 0; lane < kLanes; ++lane) {
        lanes[lane] = active[lane] && meanWeights_[0][lane] > 0;
        ridges[lane] = laneRidges_ ? laneRidges_[lane] : settings_->transportRidge;
    }
    if (!laneRidges_ && settings_->texelRidges) {
        chooseTexelRidges(lanes, ridges);
    }
    for (int lane = 0; lane < kLanes; ++lane) {
        if (lanes[lane]) {
            out_->transportRidge[lane] = ridges[lane];
        }
    }
    LaneTransport t;
    solveTransport(0, lanes, ridges, identityLanes_, t, fitted);
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!fitted[lane]) {
            continue;
        }
        for (int k = 0; k < model::kTransportTerms; ++k) {
            const auto value = static_cast<float>(t[transportIndex(k, lane)]);
            for (int c = 0; c < model::kTransportChannels; ++c) {
                out_->transport[lane][c * model::kTransportTerms + k] = value;
            }
        }
        luminanceWeight_[lane] = meanWeights_[0][lane];
    }
    // Every channel's T is the luminance T until a colour fit or tint follows.
    sampleLanes(t, fitted,
                {{transport_.data(), kLanes},
                 {&channelTransport_[0], 3 * kLanes},
                 {&channelTransport_[kLanes], 3 * kLanes},
                 {&channelTransport_[2 * kLanes], 3 * kLanes}});
}

// A tilt's colour: the luminance T just fitted, each channel offset from it as the centre's
// was (the offsets keep the luminance: the centre's channels sum to its T). A tilt of a few
// degrees moves the shading, not the tint of light off the clay or across a lamp's beam, and
// the three colour fits were most of a tilt's time.
void ExtendedChunkFit::carryCentreTint(const bool (&lanes)[kLanes],
                                       const ExtendedChunkSolution& centre) {
    ExtendedChunkSolution& out = *out_;
    LaneTransport channel[model::kTransportChannels];
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!lanes[lane]) {
            continue;
        }
        TransportVector grey, centreGrey = TransportVector::Zero();
        for (int k = 0; k < model::kTransportTerms; ++k) {
            grey[k] = static_cast<double>(out.transport[lane][k]);
        }
        for (int c = 0; c < model::kTransportChannels; ++c) {
            for (int k = 0; k < model::kTransportTerms; ++k) {
                centreGrey[k] +=
                    kLuminance709[c] *
                    static_cast<double>(centre.transport[lane][c * model::kTransportTerms + k]);
            }
        }
        for (int c = 0; c < model::kTransportChannels; ++c) {
            for (int k = 0; k < model::kTransportTerms; ++k) {
                const double t =
                    grey[k] +
                    static_cast<double>(centre.transport[lane][c * model::kTransportTerms + k]) -
                    centreGrey[k];
                out.transport[lane][c * model::kTransportTerms + k] = static_cast<float>(t);
                channel[c][transportIndex(k, lane)] = t;
            }
        }
    }
    for (int c = 0; c < model::kTransportChannels; ++c) {
        sampleLanes(channel[c], lanes,
                    {{&channelTransport_[static_cast<std::size_t>(c) * kLanes], 3 * kLanes}});
    }
}

// Each channel's T given f: min Σ w (y_c − T_c(l) P_c)² + ρ ‖t_c − t‖², pulled towards the
// luminance T by the search's ridge, over the samples the luminance fit used;
// then shifted so that the channels' luminance is T again. What T explains has a
// colour (light off the clay, a lamp's tint across its beam: on realrti-dev item7 the
// photographs under high lights are 3–5% bluer than a grey T draws them). Letting the
// channels change T's luminance as well cost the canvas (item5) 0.7 dB.
void ExtendedChunkFit::fitColourTransport(const bool (&lanes)[kLanes]) {
    ExtendedChunkSolution& out = *out_;
    LaneTransport grey;
    for (int lane = 0; lane < kLanes; ++lane) {
        for (int k = 0; k < model::kTransportTerms; ++k) {
            grey[transportIndex(k, lane)] = static_cast<double>(out.transport[lane][k]);
        }
    }
    LaneTransport colour[model::kTransportChannels];
    for (int c = 0; c < model::kTransportChannels; ++c) {
        // The luminance fit's ridge, in its units: a channel with little light of its own
        // (a dark background's red) stays grey, where a pull relative to its own faint
        // samples let quantization noise through, and the shift below carried it into the
        // other channels (SynthRTI Multi/Object1/material2: 45.8 → 24.0 dB).
        bool solvable[kLanes];
        double ridges[kLanes] = {};
        for (int lane = 0; lane < kLanes; ++lane) {
            const double meanWeight = meanWeights_[1 + c][lane];
            solvable[lane] = lanes[lane] && meanWeight > 0;
            if (solvable[lane]) {
                ridges[lane] = settings_->transportRidge * luminanceWeight_[lane] / meanWeight;
            }
        }
        bool solved[kLanes];
        solveTransport(1 + c, solvable, ridges, grey, colour[c], solved);
        for (int lane = 0; lane < kLanes; ++lane) {
            if (!solved[lane]) {  // the channel keeps the luminance T
                for (int k = 0; k < model::kTransportTerms; ++k) {
                    colour[c][transportIndex(k, lane)] = grey[transportIndex(k, lane)];
                }
            }
        }
    }
    // Only the colour: the channels shift together until their luminance is T's again.
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!lanes[lane]) {
            continue;
        }
        for (int k = 0; k < model::kTransportTerms; ++k) {
            const std::size_t i = transportIndex(k, lane);
            const double shift =
                grey[i] - (kLuminance709[0] * colour[0][i] + kLuminance709[1] * colour[1][i] +
                           kLuminance709[2] * colour[2][i]);
            for (int c = 0; c < model::kTransportChannels; ++c) {
                colour[c][i] += shift;
                out.transport[lane][c * model::kTransportTerms + k] =
                    static_cast<float>(colour[c][i]);
            }
        }
    }
    for (int c = 0; c < model::kTransportChannels; ++c) {
        sampleLanes(colour[c], lanes,
                    {{&channelTransport_[static_cast<std::size_t>(c) * kLanes], 3 * kLanes}});
    }
}

// Shadows only darken: residuals far below the model (relative to the lane's robust
// scale) get Tukey weights, residuals above it keep weight 1, so the BRDF follows the
// lit appearance and the shadowing is left for T. Clipped samples the model already
// reaches are censored.
void ExtendedChunkFit::updateShadowWeights(int lane) {
    magnitudes_.clear();
    double mean = 0;
    for (int s = 0; s < samples_; ++s) {
        const std::size_t i = at(s, lane);
        const double model = static_cast<double>(transport_[i]) * predicted_[i];
        const double observed = observedLuminance(s, lane);
        censored_[i] = saturated_[i] && model >= observed;
        if (usable(i)) {
            magnitudes_.push_back(std::fabs(observed - model));
            mean += observed;
        }
    }
    if (magnitudes_.empty()) {
        return;
    }
    mean /= static_cast<double>(magnitudes_.size());
    std::nth_element(magnitudes_.begin(),
                     magnitudes_.begin() + static_cast<long>(magnitudes_.size() / 2),
                     magnitudes_.end());
    const double scale = std::max(1.4826 * magnitudes_[magnitudes_.size() / 2], 1e-3 * mean + 1e-6);
    const double cutoff = settings_->shadowCutoff * scale;
    for (int s = 0; s < samples_; ++s) {
        const std::size_t i = at(s, lane);
        const double r =
            observedLuminance(s, lane) - static_cast<double>(transport_[i]) * predicted_[i];
        const double u = r / cutoff;
        robust_[i] =
            r >= 0 ? 1.0f : (u > -1 ? static_cast<float>((1 - u * u) * (1 - u * u)) : 0.0f);
    }
}

// f given T: observations y / T, weights T² (the least-squares form of y ≈ T f), times the
// shadow weights; every lane at once, by the paper's kernel.
void ExtendedChunkFit::fitBrdf(const ChunkGeometry& geometry, const KernelLightSet& lights,
                               NormalEquationSums& sums) {
    const ExtendedFitSettings& settings = *settings_;
    // Sample by sample with the lanes innermost, so that the loops vectorize.
    for (int s = 0; s < samples_; ++s) {
        bool use[kLanes];
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t i = at(s, lane);
            const double t = static_cast<double>(transport_[i]);
            use[lane] = t >= settings.minimumTransport && !censored_[i];
            scaledWeights_[i] = use[lane]
                                    ? static_cast<float>(static_cast<double>(weights_[i]) *
                                                         static_cast<double>(robust_[i]) * t * t)
                                    : 0.0f;
        }
        for (int c = 0; c < 3; ++c) {
            const std::size_t v0 = valueAt(s, c, 0);
            const float* __restrict values = &values_[v0];
            const float* __restrict transport = &channelTransport_[v0];
            float* __restrict scaled = &scaled_[v0];
            for (int lane = 0; lane < kLanes; ++lane) {
                // Divided for every lane and kept where used: so the loop vectorizes.
                const double quotient =
                    static_cast<double>(values[lane]) /
                    std::max(static_cast<double>(transport[lane]), settings.minimumTransport);
                scaled[lane] = use[lane] ? static_cast<float>(quotient) : 0.0f;
            }
        }
    }
    ChunkObservations observations;
    observations.values = scaled_.data();
    observations.sampleStride = 3 * kLanes;
    observations.channelStride = kLanes;
    observations.weights = scaledWeights_.data();
    observations.weightStride = kLanes;
    accumulateNormalEquations(geometry, lights, observations, settings.harmonics,
                              settings.precision, sums);
    solveNormalEquations(sums, settings.harmonics, settings.lambda, out_->brdf);
}

void ExtendedChunkFit::rememberCentre() {
    centreTransport_ = transport_;
    centreChannelTransport_ = channelTransport_;
    std::copy_n(luminanceWeight_, kLanes, centreLuminanceWeight_);
}

void ExtendedChunkFit::tryTilt(const ChunkGeometry& candidate, const KernelLightSet& lights,
                               const ExtendedChunkSolution& centre, ExtendedChunkSolution& out,
                               bool refitColour) {
    out_ = &out;
    laneRidges_ = centre.transportRidge;
    transport_ = centreTransport_;
    channelTransport_ = centreChannelTransport_;
    std::copy_n(centreLuminanceWeight_, kLanes, luminanceWeight_);
    out.brdf = centre.brdf;
    std::copy_n(&centre.transport[0][0], kLanes * model::kTransportValues, &out.transport[0][0]);
    std::copy_n(centre.transportRidge, kLanes, out.transportRidge);
    shade(candidate);
    bool active[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) {
        active[lane] = out.brdf.valid[lane];
    }
    predictLanes();
    buildTransportEquations(active, refitColour && settings_->colourTransport);
    bool fitted[kLanes];
    fitTransport(active, fitted);
    if (settings_->colourTransport) {
        bool colour[kLanes];
        for (int lane = 0; lane < kLanes; ++lane) {
            colour[lane] = fitted[lane] && (refitColour ? luminanceWeight_[lane] > 0
                                                        : centreLuminanceWeight_[lane] > 0);
        }
        if (refitColour) {
            fitColourTransport(colour);
        } else {
            carryCentreTint(colour, centre);
        }
    }
    auto sums = std::make_unique<NormalEquationSums>();
    fitBrdf(candidate, lights, *sums);
    trainingErrors();
}

// A texel whose transport leaves too few samples (nearly always in shadow) keeps the
// plain fit and T ≡ 1 rather than dropping out.
void ExtendedChunkFit::keepPlainFit(const ChunkSolution& firstRound) {
    ExtendedChunkSolution& out = *out_;
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!out.brdf.valid[lane] && firstRound.valid[lane]) {
            std::copy_n(&firstRound.coefficients[lane][0][0], kChannels * kMaxCoefficients,
                        &out.brdf.coefficients[lane][0][0]);
            std::copy_n(firstRound.rms[lane], kChannels, out.brdf.rms[lane]);
            out.brdf.valid[lane] = true;
            setGreyTransport(lane, identity_);
            luminanceWeight_[lane] = 0;
            for (int s = 0; s < samples_; ++s) {
                transport_[at(s, lane)] = 1.0f;
                for (int c = 0; c < 3; ++c) {
                    channelTransport_[valueAt(s, c, lane)] = 1.0f;
                }
            }
        }
    }
}

// The final model's squared error on each valid lane's training samples, all three channels,
// each under its own T as the last BRDF fit took it (channelTransport_, which every T fit and
// fallback keeps in step with the coefficients).
void ExtendedChunkFit::trainingErrors() {
    ExtendedChunkSolution& out = *out_;
    double error[kLanes];
    everyLaneError(out.brdf, settings_->harmonics, laneSamples(),
                   {weights_.data(), saturated_.data(), values_.data(), channelTransport_.data()},
                   error);
    for (int lane = 0; lane < kLanes; ++lane) {
        out.trainingError[lane] = out.brdf.valid[lane] ? error[lane] : 0.0;
    }
}

// The thread's fit: its buffers hold every sample of every lane and are kept from one chunk
// to the next.
ExtendedChunkFit& threadFit() {
    thread_local ExtendedChunkFit fit;
    return fit;
}

}  // namespace

void fitChunkExtended(const capture::Capture& capture, const ExtendedLightTable& table,
                      const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                      const KernelLightSet& lights, const capture::SampleBand& band, int row,
                      int x0, const ExtendedFitSettings& settings, ExtendedChunkSolution& out,
                      const double* laneRidges) {
    threadFit().fit(capture, table, geometry, laneValid, lights, band, row, x0, settings, out,
                    laneRidges);
}

namespace {

// n tilted by `radians` towards the azimuth `phi` of its own tangent plane (any tangent frame
// will do: the pattern covers all azimuths).
proto::Vec3d tilted(const proto::Vec3d& n, double radians, double phi) {
    const auto frame = proto::tangentFrame(n, proto::Vec3d{1, 0, 0}, proto::Vec3d{0, 1, 0});
    const double u = std::tan(radians) * std::cos(phi), v = std::tan(radians) * std::sin(phi);
    return proto::normalized(proto::Vec3d{n.x + u * frame.t.x + v * frame.b.x,
                                          n.y + u * frame.t.y + v * frame.b.y,
                                          n.z + u * frame.t.z + v * frame.b.z});
}

}  // namespace

void fitChunkExtendedRefiningNormals(const capture::Capture& capture,
                                     const ExtendedLightTable& table, ChunkGeometry& geometry,
                                     const bool (&laneValid)[kLanes], const KernelLightSet& lights,
                                     const capture::SampleBand& band, int row, int x0,
                                     const ExtendedFitSettings& settings,
                                     ExtendedChunkSolution& out) {
    ExtendedChunkFit& fit = threadFit();
    fit.fit(capture, table, geometry, laneValid, lights, band, row, x0, settings, out, nullptr);
    if (!(settings.normalSearchDegrees > 0)) {
        return;
    }
    // Along the tangent frame's ± axes: 8 directions (the diagonals too) cost twice the fits
    // for +0.02 dB on realrti-dev.
    constexpr int kDirections = 4;
    thread_local std::unique_ptr<ExtendedChunkSolution> trial;
    if (!trial) {
        trial = std::make_unique<ExtendedChunkSolution>();
    }
    // Every tilt is tried from the centre's fit (tryTilt): T fitted once to the centre's f as
    // the tilt shades it, then f once; the normals found are then fitted whole, T and all.
    // Trying a tilt by f alone under the centre's T left item3 0.5 dB short: T had taken up
    // part of the centre's error and judged every tilt in the centre's favour.
    fit.rememberCentre();
    thread_local std::unique_ptr<ExtendedChunkSolution> centre;
    if (!centre) {
        centre = std::make_unique<ExtendedChunkSolution>();
    }
    *centre = out;
    bool moved[kLanes] = {};
    ChunkGeometry candidate = geometry;
    double radians = settings.normalSearchDegrees * std::numbers::pi / 180.0;
    for (int step = 0; step < settings.normalSearchSteps; ++step, radians *= 0.5) {
        const ChunkGeometry around = geometry;  // each step searches around the last best
        for (int direction = 0; direction < kDirections; ++direction) {
            const double phi = 2.0 * std::numbers::pi * direction / kDirections;
            for (int lane = 0; lane < kLanes; ++lane) {
                const proto::Vec3d n =
                    tilted({around.normal[0][lane], around.normal[1][lane], around.normal[2][lane]},
                           radians, phi);
                candidate.normal[0][lane] = static_cast<float>(n.x);
                candidate.normal[1][lane] = static_cast<float>(n.y);
                candidate.normal[2][lane] = static_cast<float>(n.z);
            }
            // T's colour is fitted again only in the last, finest step: the colour fits (three
            // T fits) were most of a tilt's time. On realrti-dev (r0), carrying the centre's
            // tint through every step cost the canvas (item5) 0.13 dB; refitting it in the
            // last step keeps every item within 0.03 dB of refitting it always (mean 32.43 dB
            // both), and the final fit takes 0.55-0.8x the time.
            fit.tryTilt(candidate, lights, *centre, *trial, step + 1 == settings.normalSearchSteps);
            for (int lane = 0; lane < kLanes; ++lane) {
                if (!laneValid[lane] || !trial->brdf.valid[lane] ||
                    (out.brdf.valid[lane] &&
                     !(trial->trainingError[lane] < out.trainingError[lane]))) {
                    continue;
                }
                for (int a = 0; a < 3; ++a) {
                    geometry.normal[a][lane] = candidate.normal[a][lane];
                }
                std::copy_n(&trial->brdf.coefficients[lane][0][0], kChannels * kMaxCoefficients,
                            &out.brdf.coefficients[lane][0][0]);
                std::copy_n(trial->brdf.rms[lane], kChannels, out.brdf.rms[lane]);
                std::copy_n(trial->transport[lane], model::kTransportValues, out.transport[lane]);
                out.brdf.valid[lane] = true;
                out.trainingError[lane] = trial->trainingError[lane];
                moved[lane] = true;
            }
        }
    }
    if (std::none_of(moved, moved + kLanes, [](bool m) { return m; })) {
        return;
    }
    // The normals found, fitted whole: f and T again, under the centre's ridges.
    fit.refit(geometry, laneValid, lights, *trial, centre->transportRidge);
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!moved[lane] || !trial->brdf.valid[lane] ||
            !(trial->trainingError[lane] < out.trainingError[lane])) {
            continue;
        }
        std::copy_n(&trial->brdf.coefficients[lane][0][0], kChannels * kMaxCoefficients,
                    &out.brdf.coefficients[lane][0][0]);
        std::copy_n(trial->brdf.rms[lane], kChannels, out.brdf.rms[lane]);
        std::copy_n(trial->transport[lane], model::kTransportValues, out.transport[lane]);
        out.trainingError[lane] = trial->trainingError[lane];
    }
}

}  // namespace vpe::fit
