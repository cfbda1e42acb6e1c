// SPDX-License-Identifier: MIT
// Alternating fit of BRDF and light transport.
#include "vpe/fit/extended_chunk_fit.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include <Eigen/Dense>

#include "vpe/proto/detail_normal.h"
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

using TransportMatrix = Eigen::Matrix<double, kTransportTerms, kTransportTerms>;
using TransportVector = Eigen::Matrix<double, kTransportTerms, 1>;

// One sample of a texel's T fit: T(l)·P ≈ L with weight w.
struct TransportSample {
    const double* basis;  // T's basis at the sample's light, kTransportTerms
    double weight, predicted, observed;
};

// The normal equations of Σ w (y − T(l) P)² over `samples`.
struct TransportEquations {
    TransportMatrix a = TransportMatrix::Zero();
    TransportVector b = TransportVector::Zero();
    double meanWeight = 0;  // of w P², the scale the ridges are relative to

    explicit TransportEquations(const std::vector<TransportSample>& samples) {
        double weightSum = 0;
        for (const TransportSample& sample : samples) {
            const Eigen::Map<const TransportVector> h(sample.basis);
            const double wp = sample.weight * sample.predicted;
            a.noalias() += (wp * sample.predicted) * h * h.transpose();
            b.noalias() += (wp * sample.observed) * h;
            weightSum += wp * sample.predicted;
        }
        meanWeight = samples.empty() ? 0.0 : weightSum / static_cast<double>(samples.size());
    }
    bool solvable() const { return meanWeight > 0; }
    // min Σ w (y − T P)² + ridge · meanWeight · ‖t − prior‖²; not finite when it fails.
    TransportVector solve(double ridge, const TransportVector& prior) const {
        TransportMatrix regularized = a;
        regularized.diagonal().array() += ridge * meanWeight;
        return regularized.ldlt().solve(b + ridge * meanWeight * prior);
    }
};

// T's ridge for one texel, relative to its mean sample weight: the search's `ridge`, or a
// weaker one (0.3, 0.1, 0.03 or 0.01 of it, none below the weakest the search tries) where
// the texel's own lights call for it. They call when the ridge fit's leave-one-light-out
// error (PRESS, in closed form: residual / (1 − leverage)) falls by at least a fifth, about
// one standard error of a PRESS over some forty lights; on flat texels a weaker ridge only
// fits noise. On realrti-dev item7 (clay relief) the veins are such texels: the light falls
// off their flanks faster than the search's ridge lets T draw (+0.3 dB on held-out lights).
double texelTransportRidge(const TransportEquations& equations,
                           const std::vector<TransportSample>& samples,
                           const TransportVector& prior, double ridge) {
    constexpr double kWeakest = 0.01;
    constexpr double kRequiredGain = 0.8;
    double chosen = ridge, best = 0;
    for (double factor : {1.0, 0.3, 0.1, 0.03, 0.01}) {
        const double candidate = ridge * factor;
        if (factor < 1 && candidate < kWeakest * (1 - 1e-9)) {
            break;
        }
        TransportMatrix regularized = equations.a;
        regularized.diagonal().array() += candidate * equations.meanWeight;
        const TransportMatrix inverse = regularized.inverse();
        const TransportVector t =
            inverse * (equations.b + candidate * equations.meanWeight * prior);
        if (!t.allFinite()) {
            continue;
        }
        double press = 0;
        for (const TransportSample& sample : samples) {
            const Eigen::Map<const TransportVector> h(sample.basis);
            const double leverage =
                sample.weight * sample.predicted * sample.predicted * h.dot(inverse * h);
            const double residual =
                (sample.observed - sample.predicted * h.dot(t)) / std::max(1e-3, 1 - leverage);
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

ExtendedLightTable::ExtendedLightTable(const Capture& capture) {
    transportBasis.reserve(capture.images.size());
    for (const CaptureImage& image : capture.images) {
        std::array<double, kTransportTerms> basis;
        lightTransportBasis(transportDirection(capture, image), basis.data());
        transportBasis.push_back(basis);
    }
}

void fitChunkExtended(const Capture& capture, const ExtendedLightTable& table,
                      const ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                      const KernelLightSet& lights, const SampleBand& band, int row, int x0,
                      const ExtendedFitSettings& settings, ExtendedChunkSolution& out) {
    const int samples = lights.count;
    const std::size_t laneBlock = static_cast<std::size_t>(samples) * kLanes;
    // Per sample and lane: raw observations, usable weight, saturation, model geometry.
    thread_local std::vector<float> values, weights, scaled, scaledWeights, transport,
        channelTransport;
    thread_local std::vector<std::uint8_t> saturated, censored;
    thread_local std::vector<double> cosD, cosS, irradiance;
    values.resize(laneBlock * 3);
    scaled.resize(laneBlock * 3);
    weights.resize(laneBlock);
    scaledWeights.resize(laneBlock);
    transport.assign(laneBlock, 1.0f);
    channelTransport.assign(laneBlock * 3, 1.0f);  // per sample, channel and lane, as values
    saturated.resize(laneBlock);
    censored.assign(laneBlock, 0);
    cosD.resize(laneBlock);
    cosS.resize(laneBlock);
    irradiance.resize(laneBlock);
    for (int s = 0; s < samples; ++s) {
        const CaptureImage& image = capture.images[static_cast<std::size_t>(s)];
        for (int lane = 0; lane < kLanes; ++lane) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            weights[at] = band.weight(s, row, x0 + lane);
            saturated[at] = band.isSaturated(s, row, x0 + lane) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                values[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane] =
                    band.value(s, c, row, x0 + lane);
            }
            const Vec3d n{geometry.normal[0][lane], geometry.normal[1][lane],
                          geometry.normal[2][lane]};
            const Vec3d v{geometry.view[0][lane], geometry.view[1][lane], geometry.view[2][lane]};
            const Vec3d p{geometry.position[0][lane], geometry.position[1][lane],
                          geometry.position[2][lane]};
            const IncidentLight light = incidentLight(capture, image, p);
            const auto angles = proto::reflectionAngles(n, light.direction, v);
            cosD[at] = angles.cosThetaD;
            cosS[at] = angles.cosThetaS;
            irradiance[at] = light.irradiance;
        }
    }
    auto setGreyTransport = [&](int lane, const double* coefficients) {
        for (int c = 0; c < kTransportChannels; ++c) {
            for (int k = 0; k < kTransportTerms; ++k) {
                out.transport[lane][c * kTransportTerms + k] = static_cast<float>(coefficients[k]);
            }
        }
    };
    double identity[kTransportTerms];
    identityTransport(identity);
    for (int lane = 0; lane < kLanes; ++lane) {
        setGreyTransport(lane, identity);
    }
    // The luminance T fit's mean weight per lane; 0 while the lane has no fitted T.
    double luminanceWeight[kLanes] = {};

    thread_local std::vector<float> robust;  // shadow down-weighting of the BRDF fit
    robust.assign(laneBlock, 1.0f);
    std::vector<double> predicted(static_cast<std::size_t>(samples));
    std::vector<double> magnitudes;
    auto observedLuminance = [&](int s, int lane) {
        const std::size_t base = static_cast<std::size_t>(s) * 3 * kLanes + lane;
        return luminance(values[base], values[base + kLanes], values[base + 2 * kLanes]);
    };
    // The BRDF's luminance prediction of every sample of a lane, in image units.
    auto predictLane = [&](int lane) {
        for (int s = 0; s < samples; ++s) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            double rgb[3];
            for (int c = 0; c < 3; ++c) {
                rgb[c] = irradiance[at] * proto::evaluateFourierBrdf(out.brdf.coefficients[lane][c],
                                                                     settings.harmonics, cosD[at],
                                                                     cosS[at]);
            }
            predicted[static_cast<std::size_t>(s)] = luminance(rgb[0], rgb[1], rgb[2]);
        }
    };
    // T given f, on luminance: min Σ w (L − T(l) P)² + ρ ‖t − t₁‖², ρ the texel's own
    // (texelTransportRidge). Every channel takes it.
    thread_local std::vector<TransportSample> fitted;
    const Eigen::Map<const TransportVector> one(identity);
    // The lane's usable samples (`channel` < 0: luminance), with the prediction P of `predict`.
    auto gatherSamples = [&](int lane, int channel, auto predict) {
        fitted.clear();
        for (int s = 0; s < samples; ++s) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            if (weights[at] <= 0 || censored[at]) {
                continue;
            }
            const double observed =
                channel < 0
                    ? observedLuminance(s, lane)
                    : static_cast<double>(
                          values[(static_cast<std::size_t>(s) * 3 + channel) * kLanes + lane]);
            fitted.push_back({table.transportBasis[static_cast<std::size_t>(s)].data(), weights[at],
                              predict(s, at), observed});
        }
    };
    auto fitTransport = [&](int lane) {
        gatherSamples(lane, -1,
                      [&](int s, std::size_t) { return predicted[static_cast<std::size_t>(s)]; });
        const TransportEquations equations(fitted);
        if (!equations.solvable()) {
            return;
        }
        const double ridge = settings.texelRidges ? texelTransportRidge(equations, fitted, one,
                                                                        settings.transportRidge)
                                                  : settings.transportRidge;
        const TransportVector t = equations.solve(ridge, one);
        if (!t.allFinite()) {
            return;
        }
        setGreyTransport(lane, t.data());
        luminanceWeight[lane] = equations.meanWeight;
        sampleTransport(table, t, samples, &transport[lane], kLanes);
        for (int c = 0; c < 3; ++c) {
            sampleTransport(table, t, samples, &channelTransport[c * kLanes + lane], 3 * kLanes);
        }
    };
    // Each channel's T given f: min Σ w (y_c − T_c(l) P_c)² + ρ ‖t_c − t‖², pulled towards the
    // luminance T by the search's ridge, over the samples the luminance fit used;
    // then shifted so that the channels' luminance is T again. What T explains has a
    // colour (light off the clay, a lamp's tint across its beam: on realrti-dev item7 the
    // photographs under high lights are 3–5% bluer than a grey T draws them). Letting the
    // channels change T's luminance as well cost the canvas (item5) 0.7 dB.
    auto fitColourTransport = [&](int lane) {
        TransportVector grey;
        for (int k = 0; k < kTransportTerms; ++k) {
            grey[k] = static_cast<double>(out.transport[lane][k]);
        }
        TransportVector colour[kTransportChannels] = {grey, grey, grey};
        for (int c = 0; c < kTransportChannels; ++c) {
            gatherSamples(lane, c, [&](int, std::size_t at) {
                return irradiance[at] * proto::evaluateFourierBrdf(out.brdf.coefficients[lane][c],
                                                                   settings.harmonics, cosD[at],
                                                                   cosS[at]);
            });
            const TransportEquations equations(fitted);
            if (!equations.solvable()) {
                continue;  // the channel keeps the luminance T
            }
            // The luminance fit's ridge, in its units: a channel with little light of its own
            // (a dark background's red) stays grey, where a pull relative to its own faint
            // samples let quantization noise through, and the shift below carried it into the
            // other channels (SynthRTI Multi/Object1/material2: 45.8 → 24.0 dB).
            const TransportVector t = equations.solve(
                settings.transportRidge * luminanceWeight[lane] / equations.meanWeight, grey);
            if (t.allFinite()) {
                colour[c] = t;
            }
        }
        // Only the colour: the channels shift together until their luminance is T's again.
        const TransportVector shift =
            grey - (kLuminance709[0] * colour[0] + kLuminance709[1] * colour[1] +
                    kLuminance709[2] * colour[2]);
        for (int c = 0; c < kTransportChannels; ++c) {
            const TransportVector t = colour[c] + shift;
            for (int k = 0; k < kTransportTerms; ++k) {
                out.transport[lane][c * kTransportTerms + k] = static_cast<float>(t[k]);
            }
            sampleTransport(table, t, samples, &channelTransport[c * kLanes + lane], 3 * kLanes);
        }
    };
    // Shadows only darken: residuals far below the model (relative to the lane's robust
    // scale) get Tukey weights, residuals above it keep weight 1, so the BRDF follows the
    // lit appearance and the shadowing is left for T. Clipped samples the model already
    // reaches are censored.
    auto updateRobustWeights = [&](int lane) {
        magnitudes.clear();
        double mean = 0;
        for (int s = 0; s < samples; ++s) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            const double model =
                static_cast<double>(transport[at]) * predicted[static_cast<std::size_t>(s)];
            const double observed = observedLuminance(s, lane);
            censored[at] = saturated[at] && model >= observed;
            if (weights[at] > 0 && !censored[at]) {
                magnitudes.push_back(std::fabs(observed - model));
                mean += observed;
            }
        }
        if (magnitudes.empty()) {
            return;
        }
        mean /= static_cast<double>(magnitudes.size());
        std::nth_element(magnitudes.begin(),
                         magnitudes.begin() + static_cast<long>(magnitudes.size() / 2),
                         magnitudes.end());
        const double scale =
            std::max(1.4826 * magnitudes[magnitudes.size() / 2], 1e-3 * mean + 1e-6);
        const double cutoff = settings.shadowCutoff * scale;
        for (int s = 0; s < samples; ++s) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            const double r =
                observedLuminance(s, lane) -
                static_cast<double>(transport[at]) * predicted[static_cast<std::size_t>(s)];
            const double u = r / cutoff;
            robust[at] =
                r >= 0 ? 1.0f : (u > -1 ? static_cast<float>((1 - u * u) * (1 - u * u)) : 0.0f);
        }
    };

    // The final model's squared error on the lane's training samples, all three channels,
    // each under its own T.
    auto trainingError = [&](int lane) {
        double error = 0;
        for (int s = 0; s < samples; ++s) {
            const std::size_t at = static_cast<std::size_t>(s) * kLanes + lane;
            if (weights[at] <= 0) {
                continue;
            }
            const double* basis = table.transportBasis[static_cast<std::size_t>(s)].data();
            for (int c = 0; c < 3; ++c) {
                double t = 0;
                for (int k = 0; k < kTransportTerms; ++k) {
                    t += static_cast<double>(out.transport[lane][c * kTransportTerms + k]) *
                         basis[k];
                }
                const double shading = std::clamp(t, 0.0, 4.0) * irradiance[at];
                const double model =
                    shading * proto::evaluateFourierBrdf(out.brdf.coefficients[lane][c],
                                                         settings.harmonics, cosD[at], cosS[at]);
                const double observed = static_cast<double>(
                    values[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane]);
                if (!(saturated[at] && model >= observed)) {
                    error +=
                        static_cast<double>(weights[at]) * (observed - model) * (observed - model);
                }
            }
        }
        return error;
    };

    auto sums = std::make_unique<NormalEquationSums>();
    auto firstRound = std::make_unique<ChunkSolution>();
    const int rounds = std::max(1, settings.rounds);
    for (int round = 0;; ++round) {
        // f given T: observations y / T, weights T² (the least-squares form of y ≈ T f),
        // times the shadow weights.
        for (std::size_t at = 0; at < laneBlock; ++at) {
            const double t = static_cast<double>(transport[at]);
            const bool use = t >= settings.minimumTransport && !censored[at];
            scaledWeights[at] = use ? static_cast<float>(static_cast<double>(weights[at]) *
                                                         static_cast<double>(robust[at]) * t * t)
                                    : 0.0f;
            const std::size_t s = at / kLanes, lane = at % kLanes;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (s * 3 + c) * kLanes + lane;
                scaled[i] =
                    use ? static_cast<float>(static_cast<double>(values[i]) /
                                             std::max(static_cast<double>(channelTransport[i]),
                                                      settings.minimumTransport))
                        : 0.0f;
            }
        }
        ChunkObservations observations;
        observations.values = scaled.data();
        observations.sampleStride = 3 * kLanes;
        observations.channelStride = kLanes;
        observations.weights = scaledWeights.data();
        observations.weightStride = kLanes;
        accumulateNormalEquations(geometry, lights, observations, settings.harmonics,
                                  settings.precision, *sums);
        solveNormalEquations(*sums, settings.harmonics, settings.lambda, out.brdf);
        if (round == 0) {
            *firstRound = out.brdf;
        }
        if (round + 1 >= rounds) {
            break;
        }
        // Round 0's BRDF still carries the shadows, so T waits for the reweighted fit.
        for (int lane = 0; lane < kLanes; ++lane) {
            if (!laneValid[lane] || !out.brdf.valid[lane]) {
                continue;
            }
            predictLane(lane);
            if (round >= 1) {
                fitTransport(lane);
                if (settings.colourTransport && luminanceWeight[lane] > 0) {
                    fitColourTransport(lane);
                }
            }
            updateRobustWeights(lane);
        }
    }
    // A texel whose transport leaves too few samples (nearly always in shadow) keeps the
    // plain fit and T ≡ 1 rather than dropping out.
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!out.brdf.valid[lane] && firstRound->valid[lane]) {
            std::copy_n(&firstRound->coefficients[lane][0][0], kChannels * kMaxCoefficients,
                        &out.brdf.coefficients[lane][0][0]);
            std::copy_n(firstRound->rms[lane], kChannels, out.brdf.rms[lane]);
            out.brdf.valid[lane] = true;
            setGreyTransport(lane, identity);
            luminanceWeight[lane] = 0;
            for (int s = 0; s < samples; ++s) {
                transport[static_cast<std::size_t>(s) * kLanes + lane] = 1.0f;
                for (int c = 0; c < 3; ++c) {
                    channelTransport[(static_cast<std::size_t>(s) * 3 + c) * kLanes + lane] = 1.0f;
                }
            }
        }
    }
    for (int lane = 0; lane < kLanes; ++lane) {
        out.trainingError[lane] = out.brdf.valid[lane] ? trainingError(lane) : 0.0;
    }
}

namespace {

// n tilted by `radians` towards the azimuth `phi` of its own tangent plane (any tangent frame
// will do: the pattern covers all azimuths).
Vec3d tilted(const Vec3d& n, double radians, double phi) {
    const auto frame = proto::tangentFrame(n, Vec3d{1, 0, 0}, Vec3d{0, 1, 0});
    const double u = std::tan(radians) * std::cos(phi), v = std::tan(radians) * std::sin(phi);
    return proto::normalized(Vec3d{n.x + u * frame.t.x + v * frame.b.x,
                                   n.y + u * frame.t.y + v * frame.b.y,
                                   n.z + u * frame.t.z + v * frame.b.z});
}

}  // namespace

void fitChunkExtendedRefiningNormals(const Capture& capture, const ExtendedLightTable& table,
                                     ChunkGeometry& geometry, const bool (&laneValid)[kLanes],
                                     const KernelLightSet& lights, const SampleBand& band, int row,
                                     int x0, const ExtendedFitSettings& settings,
                                     ExtendedChunkSolution& out) {
    fitChunkExtended(capture, table, geometry, laneValid, lights, band, row, x0, settings, out);
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
    ChunkGeometry candidate = geometry;
    double radians = settings.normalSearchDegrees * std::numbers::pi / 180.0;
    for (int step = 0; step < settings.normalSearchSteps; ++step, radians *= 0.5) {
        const ChunkGeometry centre = geometry;  // each step searches around the last best
        for (int direction = 0; direction < kDirections; ++direction) {
            const double phi = 2.0 * std::numbers::pi * direction / kDirections;
            for (int lane = 0; lane < kLanes; ++lane) {
                const Vec3d n =
                    tilted({centre.normal[0][lane], centre.normal[1][lane], centre.normal[2][lane]},
                           radians, phi);
                candidate.normal[0][lane] = static_cast<float>(n.x);
                candidate.normal[1][lane] = static_cast<float>(n.y);
                candidate.normal[2][lane] = static_cast<float>(n.z);
            }
            fitChunkExtended(capture, table, candidate, laneValid, lights, band, row, x0, settings,
                             *trial);
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
                std::copy_n(trial->transport[lane], kTransportValues, out.transport[lane]);
                out.brdf.valid[lane] = true;
                out.trainingError[lane] = trial->trainingError[lane];
            }
        }
    }
}

}  // namespace vpe::fit
