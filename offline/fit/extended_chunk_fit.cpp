// SPDX-License-Identifier: MIT
// Alternating fit of BRDF and light transport.
#include "vpe/fit/extended_chunk_fit.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include <Eigen/Dense>

#include "vpe/fit/simd_pack.h"
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

// One sample of a texel's T fit: T(l)·P ≈ L with weight w.
struct TransportSample {
    const double* basis;  // T's basis at the sample's light, model::kTransportTerms
    double weight, predicted, observed;
};

// The normal equations of Σ w (y − T(l) P)² over a lane's samples, and their
// eigendecomposition, which makes every ridge's solution and leave-one-out error cheap
// (texelTransportRidge). Built for every lane and channel of a chunk at once
// (ExtendedChunkFit::buildTransportEquations).
struct TransportEquations {
    TransportMatrix a = TransportMatrix::Zero();
    TransportVector b = TransportVector::Zero();
    double meanWeight = 0;  // of w P², the scale the ridges are relative to

    bool solvable() const { return meanWeight > 0; }
    // min Σ w (y − T P)² + ridge · meanWeight · ‖t − prior‖²; not finite when it fails.
    // Cholesky: with a ridge the matrix is positive definite, and LLT is a third of LDLT's
    // time at this size (no pivoting); LDLT only where it fails (no ridge, degenerate lights).
    TransportVector solve(double ridge, const TransportVector& prior) const {
        TransportMatrix regularized = a;
        regularized.diagonal().array() += ridge * meanWeight;
        const TransportVector right = b + ridge * meanWeight * prior;
        const Eigen::LLT<TransportMatrix> cholesky(regularized);
        if (cholesky.info() == Eigen::Success) {
            return cholesky.solve(right);
        }
        return regularized.ldlt().solve(right);
    }
};

// T's ridge for one texel, relative to its mean sample weight: the search's `ridge`, or a
// weaker one (0.3, 0.1, 0.03 or 0.01 of it, none below the weakest the search tries) where
// the texel's own lights call for it. They call when the ridge fit's leave-one-light-out
// error (PRESS, in closed form: residual / (1 − leverage)) falls by at least a fifth, about
// one standard error of a PRESS over some forty lights; on flat texels a weaker ridge only
// fits noise. On realrti-dev item7 (clay relief) the veins are such texels: the light falls
// off their flanks faster than the search's ridge lets T draw (+0.3 dB on held-out lights).
// With a = V Λ Vᵀ once, ridge ρ's solution is V (Λ + ρ)⁻¹ Vᵀ (b + ρ t₁) and a sample's
// leverage w P² Σ_k (Vᵀh)_k² / (λ_k + ρ): each candidate costs a few operations a sample where
// an inverse and a 16 × 16 product a sample took.
double texelTransportRidge(const TransportEquations& equations,
                           const std::vector<TransportSample>& samples,
                           const TransportVector& prior, double ridge) {
    constexpr double kWeakest = 0.01;
    constexpr double kRequiredGain = 0.8;
    const Eigen::SelfAdjointEigenSolver<TransportMatrix> eigen(equations.a);
    if (eigen.info() != Eigen::Success) {
        return ridge;
    }
    const TransportMatrix& v = eigen.eigenvectors();
    const TransportVector& lambda = eigen.eigenvalues();
    const TransportVector projectedB = v.transpose() * equations.b;
    const TransportVector projectedPrior = v.transpose() * prior;
    // Each sample's basis in the eigenvectors' frame, and its weight w P².
    thread_local Eigen::Matrix<double, model::kTransportTerms, Eigen::Dynamic> projected;
    projected.resize(model::kTransportTerms, static_cast<Eigen::Index>(samples.size()));
    for (std::size_t i = 0; i < samples.size(); ++i) {
        projected.col(static_cast<Eigen::Index>(i)).noalias() =
            v.transpose() * Eigen::Map<const TransportVector>(samples[i].basis);
    }
    double chosen = ridge, best = 0;
    for (double factor : {1.0, 0.3, 0.1, 0.03, 0.01}) {
        const double candidate = ridge * factor;
        if (factor < 1 && candidate < kWeakest * (1 - 1e-9)) {
            break;
        }
        const double pull = candidate * equations.meanWeight;
        const TransportVector inverse = (lambda.array() + pull).inverse().matrix();
        const TransportVector y =
            inverse.cwiseProduct(projectedB + pull * projectedPrior);  // t in V's frame
        if (!y.allFinite()) {
            continue;
        }
        double press = 0;
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const TransportSample& sample = samples[i];
            const auto z = projected.col(static_cast<Eigen::Index>(i));
            const double leverage =
                sample.weight * sample.predicted * sample.predicted * z.cwiseAbs2().dot(inverse);
            const double residual =
                (sample.observed - sample.predicted * z.dot(y)) / std::max(1e-3, 1 - leverage);
            press += sample.weight * residual * residual;
        }
        if (factor < 1) {
            press /= kRequiredGain;
        }
        if (factor == 1 || press < best) {
            best = press;
            chosen = candidate;
        }
    }
    return chosen;
}

using DoublePack = simd::Pack<double, kLanes>;  // one value of every lane of a chunk

// A chunk's BRDF coefficients, each across the lanes: [channel][coefficient].
// Kept inside the kernels: a pack in memory that another function made may be aligned for the
// plain x86-64 build (16 bytes) where a kernel clone's AVX-512 loads expect 64.
using LaneCoefficients = DoublePack[kChannels][kMaxCoefficients];
[[gnu::always_inline]] inline void laneCoefficients(const ChunkSolution& brdf,
                                                    LaneCoefficients& out) {
    for (int c = 0; c < kChannels; ++c) {
        for (int k = 0; k < kMaxCoefficients; ++k) {
            for (int lane = 0; lane < kLanes; ++lane) {
                out[c][k].v[lane] = static_cast<double>(brdf.coefficients[lane][c][k]);
            }
        }
    }
}

// A chunk's samples as the lane kernels below read them: per sample, every lane side by side.
struct LaneSamples {
    int count = 0;
    const double* cosD = nullptr;        // [sample][lane]
    const double* cosS = nullptr;        // [sample][lane]
    const double* irradiance = nullptr;  // [sample][lane]
};

// f of sample s for every lane, per channel; inlined into each kernel clone.
[[gnu::always_inline]] inline void evaluateLanes(const LaneCoefficients& coefficients,
                                                 int harmonics, const LaneSamples& samples, int s,
                                                 DoublePack (&rgb)[3]) {
    const std::size_t i = static_cast<std::size_t>(s) * kLanes;
    proto::evaluateFourierBrdfRgb(&coefficients[0][0], kMaxCoefficients, harmonics,
                                  DoublePack::load(samples.cosD + i),
                                  DoublePack::load(samples.cosS + i), rgb);
}

// Every lane's BRDF prediction of every sample, in image units: per channel, [sample][channel]
// [lane], and its luminance, [sample][lane]. Each lane in its own lane of a vector, with the
// same operations in the same order as one lane alone.
VPE_KERNEL_CLONES
void predictEveryLane(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                      double* rgbOut, double* luminanceOut) {
    LaneCoefficients coefficients;
    laneCoefficients(brdf, coefficients);
    for (int s = 0; s < samples.count; ++s) {
        const std::size_t i = static_cast<std::size_t>(s) * kLanes;
        DoublePack rgb[3];
        evaluateLanes(coefficients, harmonics, samples, s, rgb);
        const DoublePack irradiance = DoublePack::load(samples.irradiance + i);
        for (int c = 0; c < 3; ++c) {
            rgb[c] = irradiance * rgb[c];
            rgb[c].store(rgbOut + (static_cast<std::size_t>(s) * 3 + c) * kLanes);
        }
        (DoublePack(kLuminance709[0]) * rgb[0] + DoublePack(kLuminance709[1]) * rgb[1] +
         DoublePack(kLuminance709[2]) * rgb[2])
            .store(luminanceOut + i);
    }
}

// What a chunk's training samples are, for the error below: per sample and lane (weights,
// saturation) or per sample, channel and lane (values, each channel's T).
struct LaneObservations {
    const float* weights = nullptr;
    const std::uint8_t* saturated = nullptr;
    const float* values = nullptr;
    const float* transport = nullptr;
};

// Every lane's Σ w (y − T_c E f_c)² over its samples and channels: samples without weight, and
// clipped ones the model already reaches, count zero.
VPE_KERNEL_CLONES
void everyLaneError(const ChunkSolution& brdf, int harmonics, const LaneSamples& samples,
                    const LaneObservations& observed, double (&error)[kLanes]) {
    LaneCoefficients coefficients;
    laneCoefficients(brdf, coefficients);
    const DoublePack zero(0.0);
    DoublePack sum(0.0);
    for (int s = 0; s < samples.count; ++s) {
        const std::size_t i = static_cast<std::size_t>(s) * kLanes;
        DoublePack predicted[3];
        evaluateLanes(coefficients, harmonics, samples, s, predicted);
        const DoublePack irradiance = DoublePack::load(samples.irradiance + i);
        DoublePack weight, saturated;
        for (int lane = 0; lane < kLanes; ++lane) {
            weight.v[lane] = static_cast<double>(observed.weights[i + lane]);
            saturated.v[lane] = observed.saturated[i + lane] ? 1.0 : 0.0;
        }
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = (static_cast<std::size_t>(s) * 3 + c) * kLanes;
            DoublePack transport, value;
            for (int lane = 0; lane < kLanes; ++lane) {
                transport.v[lane] = static_cast<double>(observed.transport[v + lane]);
                value.v[lane] = static_cast<double>(observed.values[v + lane]);
            }
            const DoublePack model = transport * irradiance * predicted[c];
            const DoublePack difference = value - model;
            const auto unused = (weight.v <= 0.0) | ((saturated.v > 0.0) & (model.v >= value.v));
            sum = sum + DoublePack(unused ? zero.v : (weight * difference * difference).v);
        }
    }
    for (int lane = 0; lane < kLanes; ++lane) {
        error[lane] = sum[lane];
    }
}

// T's normal equations of every lane at once: for each channel c, a's distinct entries
// pairs[c][k] = Σ_s u[s][c] (h hᵀ)_k(s) and b's rights[c][t] = Σ_s v[s][c] h_t(s), u = w P² and
// v = w P y lane by lane ([sample][channel][lane]), h and h hᵀ each light's
// (ExtendedLightTable). The lanes sit side by side in a vector and four entries are summed at
// once, so every sum stays in a register: a lane's own loop over its samples spent its time
// loading and storing its 136 sums, and a matrix product (Eigen's) its time packing them.
//
// sumFourEntries: entries `entry` … entry + 3 of every lane's Σ_s weight[s][channel] row_s
// (rows of `rowLength` values, one per sample). Always inlined, so that it takes the kernel
// clone's instruction set.
[[gnu::always_inline]] inline void sumFourEntries(const double* rows, int rowLength,
                                                  const double* weights, int samples, int channels,
                                                  int channel, int entry, double* out) {
    DoublePack sum[4] = {DoublePack(0.0), DoublePack(0.0), DoublePack(0.0), DoublePack(0.0)};
    for (int s = 0; s < samples; ++s) {
        const DoublePack weight =
            DoublePack::load(weights + (static_cast<std::size_t>(s) * channels + channel) * kLanes);
        const double* row = rows + static_cast<std::size_t>(s) * rowLength + entry;
        for (int e = 0; e < 4; ++e) {
            sum[e] = sum[e] + weight * DoublePack(row[e]);
        }
    }
    for (int e = 0; e < 4; ++e) {
        sum[e].store(out + static_cast<std::size_t>(entry + e) * kLanes);
    }
}

VPE_KERNEL_CLONES
void sumTransportEquations(const ExtendedLightTable& table, int samples, int channels,
                           const double* u, const double* v, double* pairs, double* rights) {
    static_assert(kTransportPairs % 4 == 0 && model::kTransportTerms % 4 == 0);
    static_assert(sizeof(std::array<double, kTransportPairs>) == kTransportPairs * sizeof(double));
    if (samples == 0) {
        std::fill_n(pairs, channels * kTransportPairs * kLanes, 0.0);
        std::fill_n(rights, channels * model::kTransportTerms * kLanes, 0.0);
        return;
    }
    const double* outer = table.transportOuter.front().data();  // [sample][pair], contiguous
    const double* basis = table.transportBasis.front().data();  // [sample][term]
    for (int c = 0; c < channels; ++c) {
        for (int k = 0; k < kTransportPairs; k += 4) {
            sumFourEntries(outer, kTransportPairs, u, samples, channels, c, k,
                           pairs + static_cast<std::size_t>(c) * kTransportPairs * kLanes);
        }
        for (int t = 0; t < model::kTransportTerms; t += 4) {
            sumFourEntries(basis, model::kTransportTerms, v, samples, channels, c, t,
                           rights + static_cast<std::size_t>(c) * model::kTransportTerms * kLanes);
        }
    }
}

// T of every sample from its coefficients, at least 0 and at most 4 (the fit's own bound).
void sampleTransport(const ExtendedLightTable& table, const TransportVector& t, int samples,
                     float* out, std::size_t stride) {
    for (int s = 0; s < samples; ++s) {
        const Eigen::Map<const TransportVector> h(
            table.transportBasis[static_cast<std::size_t>(s)].data());
        out[static_cast<std::size_t>(s) * stride] =
            static_cast<float>(std::clamp(t.dot(h), 0.0, 4.0));
    }
}

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
    void setGreyTransport(int lane, const double* coefficients);
    double observedLuminance(int s, int lane) const;
    // Whether sample index i (at()) counts in T's fit and the shadow scale: it has a weight and
    // is not censored.
    bool usable(std::size_t i) const { return weights_[i] > 0 && !censored_[i]; }
    LaneSamples laneSamples() const {
        return {samples_, cosD_.data(), cosS_.data(), irradiance_.data()};
    }
    void predictLanes();
    void gatherLuminanceSamples(int lane);
    void buildTransportEquations(const bool (&lanes)[kLanes], bool colour);
    bool fitTransport(int lane);
    void carryCentreTint(int lane, const ExtendedChunkSolution& centre);
    void fitColourTransport(int lane);
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
    // The luminance T fit's mean weight per lane; 0 while the lane has no fitted T.
    double luminanceWeight_[kLanes] = {};

    // Per sample and lane: raw observations, usable weight, saturation, model geometry.
    std::vector<float> values_, weights_, scaled_, scaledWeights_, transport_, channelTransport_;
    std::vector<std::uint8_t> saturated_, censored_;
    std::vector<double> cosD_, cosS_, irradiance_;
    std::vector<proto::Vec3d>
        lightDirections_;  // per sample and lane (the candidate tilts reuse it)
    // The centre of a normal search (rememberCentre): its T per sample, and per lane the mean
    // weight of its luminance T fit.
    std::vector<float> centreTransport_, centreChannelTransport_;
    double centreLuminanceWeight_[kLanes] = {};
    std::vector<float> robust_;         // shadow down-weighting of the BRDF fit
    std::vector<double> predicted_;     // the BRDF's luminance prediction, per sample and lane
    std::vector<double> predictedRgb_;  // per sample, channel and lane (predictLanes)
    std::vector<double> magnitudes_;
    std::vector<TransportSample> fitted_;  // the samples of a texel's ridge choice
    // T's normal equations per lane: luminance, then R, G, B (buildTransportEquations), and the
    // products they are made by.
    std::vector<std::array<TransportEquations, 1 + model::kTransportChannels>> equations_ =
        std::vector<std::array<TransportEquations, 1 + model::kTransportChannels>>(kLanes);
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
    out_ = &out;
    laneRidges_ = laneRidges;
    samples_ = lights.count;
    laneBlock_ = static_cast<std::size_t>(samples_) * kLanes;
    readObservations(capture, geometry, band, row, x0);
    model::identityTransport(identity_);
    for (int lane = 0; lane < kLanes; ++lane) {
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
        }
        for (int lane = 0; lane < kLanes; ++lane) {
            if (!active[lane]) {
                continue;
            }
            if (round >= 1) {
                fitTransport(lane);
                if (settings.colourTransport && luminanceWeight_[lane] > 0) {
                    fitColourTransport(lane);
                }
            }
            updateShadowWeights(lane);
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
    transport_.assign(laneBlock_, 1.0f);
    channelTransport_.assign(laneBlock_ * 3, 1.0f);  // per sample, channel and lane, as values
    saturated_.resize(laneBlock_);
    censored_.assign(laneBlock_, 0);
    cosD_.resize(laneBlock_);
    cosS_.resize(laneBlock_);
    irradiance_.resize(laneBlock_);
    predictedRgb_.resize(laneBlock_ * 3);
    lightDirections_.resize(laneBlock_);
    for (int s = 0; s < samples_; ++s) {
        const capture::CaptureImage& image = capture.images[static_cast<std::size_t>(s)];
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t i = at(s, lane);
            weights_[i] = band.weight(s, row, x0 + lane);
            saturated_[i] = band.isSaturated(s, row, x0 + lane) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                values_[valueAt(s, c, lane)] = band.value(s, c, row, x0 + lane);
            }
            const proto::Vec3d n{geometry.normal[0][lane], geometry.normal[1][lane],
                                 geometry.normal[2][lane]};
            const proto::Vec3d v{geometry.view[0][lane], geometry.view[1][lane],
                                 geometry.view[2][lane]};
            const proto::Vec3d p{geometry.position[0][lane], geometry.position[1][lane],
                                 geometry.position[2][lane]};
            const capture::IncidentLight light = capture::incidentLight(capture, image, p);
            const auto angles = proto::reflectionAngles(n, light.direction, v);
            cosD_[i] = angles.cosThetaD;
            cosS_[i] = angles.cosThetaS;
            irradiance_[i] = light.irradiance;
            lightDirections_[i] = light.direction;
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

// The lane's usable samples for its luminance T fit, under the predictions of predictLanes.
void ExtendedChunkFit::gatherLuminanceSamples(int lane) {
    fitted_.clear();
    for (int s = 0; s < samples_; ++s) {
        const std::size_t i = at(s, lane);
        if (!usable(i)) {
            continue;
        }
        fitted_.push_back({table_->transportBasis[static_cast<std::size_t>(s)].data(), weights_[i],
                           predicted_[i], observedLuminance(s, lane)});
    }
}

// T's normal equations of the `lanes`, from the predictions of predictLanes: luminance and,
// with `colour`, each colour channel, over each lane's usable samples (the others weigh 0).
void ExtendedChunkFit::buildTransportEquations(const bool (&lanes)[kLanes], bool colour) {
    const int channels = colour ? 1 + model::kTransportChannels : 1;
    const std::size_t perSample = static_cast<std::size_t>(channels) * kLanes;
    sampleWeights_.assign(static_cast<std::size_t>(samples_) * perSample, 0.0);
    sampleRights_.assign(sampleWeights_.size(), 0.0);
    double meanWeights[kLanes][1 + model::kTransportChannels] = {};
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!lanes[lane]) {
            continue;
        }
        for (int channel = 0; channel < channels; ++channel) {
            double weightSum = 0;
            int used = 0;
            for (int s = 0; s < samples_; ++s) {
                const std::size_t i = at(s, lane);
                if (!usable(i)) {
                    continue;
                }
                const double predicted =
                    channel == 0 ? predicted_[i] : predictedRgb_[valueAt(s, channel - 1, lane)];
                const double observed =
                    channel == 0 ? observedLuminance(s, lane)
                                 : static_cast<double>(values_[valueAt(s, channel - 1, lane)]);
                const double wp = static_cast<double>(weights_[i]) * predicted;
                const std::size_t u = static_cast<std::size_t>(s) * perSample +
                                      static_cast<std::size_t>(channel) * kLanes + lane;
                sampleWeights_[u] = std::max(wp * predicted, 0.0);
                sampleRights_[u] = wp * observed;
                weightSum += wp * predicted;
                ++used;
            }
            meanWeights[lane][channel] = used > 0 ? weightSum / used : 0.0;
        }
    }
    pairSums_.resize(static_cast<std::size_t>(channels) * kTransportPairs * kLanes);
    rightSums_.resize(static_cast<std::size_t>(channels) * model::kTransportTerms * kLanes);
    sumTransportEquations(*table_, samples_, channels, sampleWeights_.data(), sampleRights_.data(),
                          pairSums_.data(), rightSums_.data());
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!lanes[lane]) {
            continue;
        }
        for (int channel = 0; channel < channels; ++channel) {
            TransportEquations& equations =
                equations_[static_cast<std::size_t>(lane)][static_cast<std::size_t>(channel)];
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
            equations.meanWeight = meanWeights[lane][channel];
        }
    }
}

// T given f, on luminance: min Σ w (L − T(l) P)² + ρ ‖t − t₁‖², ρ the texel's own
// (texelTransportRidge). Every channel takes it.
bool ExtendedChunkFit::fitTransport(int lane) {
    const Eigen::Map<const TransportVector> one(identity_);
    const TransportEquations& equations = equations_[static_cast<std::size_t>(lane)][0];
    if (!equations.solvable()) {
        return false;
    }
    double ridge = laneRidges_ ? laneRidges_[lane] : settings_->transportRidge;
    if (!laneRidges_ && settings_->texelRidges) {
        gatherLuminanceSamples(lane);
        ridge = texelTransportRidge(equations, fitted_, one, settings_->transportRidge);
    }
    out_->transportRidge[lane] = ridge;
    const TransportVector t = equations.solve(ridge, one);
    if (!t.allFinite()) {
        return false;
    }
    setGreyTransport(lane, t.data());
    luminanceWeight_[lane] = equations.meanWeight;
    sampleTransport(*table_, t, samples_, &transport_[lane], kLanes);
    for (int c = 0; c < 3; ++c) {
        sampleTransport(*table_, t, samples_, &channelTransport_[c * kLanes + lane], 3 * kLanes);
    }
    return true;
}

// A tilt's colour: the luminance T just fitted, each channel offset from it as the centre's
// was (the offsets keep the luminance: the centre's channels sum to its T). A tilt of a few
// degrees moves the shading, not the tint of light off the clay or across a lamp's beam, and
// the three colour fits were most of a tilt's time.
void ExtendedChunkFit::carryCentreTint(int lane, const ExtendedChunkSolution& centre) {
    ExtendedChunkSolution& out = *out_;
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
        TransportVector t;
        for (int k = 0; k < model::kTransportTerms; ++k) {
            t[k] = grey[k] +
                   static_cast<double>(centre.transport[lane][c * model::kTransportTerms + k]) -
                   centreGrey[k];
            out.transport[lane][c * model::kTransportTerms + k] = static_cast<float>(t[k]);
        }
        sampleTransport(*table_, t, samples_, &channelTransport_[c * kLanes + lane], 3 * kLanes);
    }
}

// Each channel's T given f: min Σ w (y_c − T_c(l) P_c)² + ρ ‖t_c − t‖², pulled towards the
// luminance T by the search's ridge, over the samples the luminance fit used;
// then shifted so that the channels' luminance is T again. What T explains has a
// colour (light off the clay, a lamp's tint across its beam: on realrti-dev item7 the
// photographs under high lights are 3–5% bluer than a grey T draws them). Letting the
// channels change T's luminance as well cost the canvas (item5) 0.7 dB.
void ExtendedChunkFit::fitColourTransport(int lane) {
    ExtendedChunkSolution& out = *out_;
    TransportVector grey;
    for (int k = 0; k < model::kTransportTerms; ++k) {
        grey[k] = static_cast<double>(out.transport[lane][k]);
    }
    TransportVector colour[model::kTransportChannels] = {grey, grey, grey};
    for (int c = 0; c < model::kTransportChannels; ++c) {
        const TransportEquations& equations = equations_[static_cast<std::size_t>(lane)][1 + c];
        if (!equations.solvable()) {
            continue;  // the channel keeps the luminance T
        }
        // The luminance fit's ridge, in its units: a channel with little light of its own
        // (a dark background's red) stays grey, where a pull relative to its own faint
        // samples let quantization noise through, and the shift below carried it into the
        // other channels (SynthRTI Multi/Object1/material2: 45.8 → 24.0 dB).
        const TransportVector t = equations.solve(
            settings_->transportRidge * luminanceWeight_[lane] / equations.meanWeight, grey);
        if (t.allFinite()) {
            colour[c] = t;
        }
    }
    // Only the colour: the channels shift together until their luminance is T's again.
    const TransportVector shift =
        grey - (kLuminance709[0] * colour[0] + kLuminance709[1] * colour[1] +
                kLuminance709[2] * colour[2]);
    for (int c = 0; c < model::kTransportChannels; ++c) {
        const TransportVector t = colour[c] + shift;
        for (int k = 0; k < model::kTransportTerms; ++k) {
            out.transport[lane][c * model::kTransportTerms + k] = static_cast<float>(t[k]);
        }
        sampleTransport(*table_, t, samples_, &channelTransport_[c * kLanes + lane], 3 * kLanes);
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
    for (std::size_t i = 0; i < laneBlock_; ++i) {
        const double t = static_cast<double>(transport_[i]);
        const bool use = t >= settings.minimumTransport && !censored_[i];
        scaledWeights_[i] = use ? static_cast<float>(static_cast<double>(weights_[i]) *
                                                     static_cast<double>(robust_[i]) * t * t)
                                : 0.0f;
        const std::size_t s = i / kLanes, lane = i % kLanes;
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = (s * 3 + c) * kLanes + lane;
            scaled_[v] =
                use ? static_cast<float>(static_cast<double>(values_[v]) /
                                         std::max(static_cast<double>(channelTransport_[v]),
                                                  settings.minimumTransport))
                    : 0.0f;
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
    for (int s = 0; s < samples_; ++s) {
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t i = at(s, lane);
            const proto::Vec3d n{candidate.normal[0][lane], candidate.normal[1][lane],
                                 candidate.normal[2][lane]};
            const proto::Vec3d v{candidate.view[0][lane], candidate.view[1][lane],
                                 candidate.view[2][lane]};
            const auto angles = proto::reflectionAngles(n, lightDirections_[i], v);
            cosD_[i] = angles.cosThetaD;
            cosS_[i] = angles.cosThetaS;
        }
    }
    bool active[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) {
        active[lane] = out.brdf.valid[lane];
    }
    predictLanes();
    buildTransportEquations(active, refitColour && settings_->colourTransport);
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!active[lane]) {
            continue;
        }
        if (!fitTransport(lane) || !settings_->colourTransport) {
            continue;
        }
        if (refitColour && luminanceWeight_[lane] > 0) {
            fitColourTransport(lane);
        } else if (!refitColour && centreLuminanceWeight_[lane] > 0) {
            carryCentreTint(lane, centre);
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
    fit.fit(capture, table, geometry, laneValid, lights, band, row, x0, settings, *trial,
            centre->transportRidge);
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
