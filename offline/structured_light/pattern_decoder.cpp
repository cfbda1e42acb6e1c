// SPDX-License-Identifier: MIT
// Gray code + phase shifting, decoded per camera pixel with Xu and Aliaga's robust bit
// classification (2007, as Moreno and Taubin use it): a bit is only read where the direct
// light alone explains it.
#include "vpe/structured_light/pattern_decoder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/quantile.h"

#include "decoding_steps.h"

namespace vpe::structured_light {

namespace {

constexpr double kPi = 3.14159265358979323846;
using detail::kGrain;
using detail::kNaN;
using detail::kNoUncertainBit;
using detail::kTooManyUncertainBits;

// A frame whose median over the lit pixels sits this far from where it must (its pair's sum, or
// inside white and black) was captured wrong: black (the camera missed it) or saturated.
constexpr double kFrameTolerance = 0.4;

struct AxisState {
    std::vector<std::uint32_t> code;  // the Gray bits read so far, above the lowest shown
    std::vector<std::int8_t> uncertain;
    std::vector<float> sine, cosine;  // Σ I_s sin δ_s, Σ I_s cos δ_s
};

// Every lit pixel's index, in order: the tests below work on these only.
std::vector<std::size_t> litPixels(const DecodedScan& scan) {
    std::vector<std::size_t> lit;
    for (std::size_t p = 0; p < scan.direct.size(); ++p) {
        if (scan.status[p] == DecodeStatus::kDecoded) {
            lit.push_back(p);
        }
    }
    return lit;
}

}  // namespace

const char* decodeStatusName(DecodeStatus status) {
    switch (status) {
        case DecodeStatus::kDecoded:
            return "decoded";
        case DecodeStatus::kDark:
            return "dark";
        case DecodeStatus::kSaturated:
            return "saturated";
        case DecodeStatus::kAmbiguous:
            return "ambiguous";
        case DecodeStatus::kLowModulation:
            return "low_modulation";
        case DecodeStatus::kInconsistent:
            return "inconsistent";
        case DecodeStatus::kEdge:
            return "edge";
    }
    return "unknown";
}

double NoiseModel::sigma(double signal) const {
    return std::sqrt(std::max(0.0, constant + perSignal * std::max(signal, 0.0)));
}

DecodedScan decodePatterns(const ScanCapture& capture, const DecodeOptions& options) {
    const proto::StructuredLightSequence& sequence = capture.sequence();
    if (!sequence.hasPhase()) {
        return detail::decodeGrayCode(capture, options);
    }
    if (!sequence.parameters().flatFields) {
        throw common::InputError(capture.folder() / proto::kScanManifestName,
                                 "phase images without white and black (flat_fields false): the "
                                 "phase is read against the flat fields");
    }
    const proto::StructuredLightParameters& parameters = sequence.parameters();
    const unsigned threads = common::resolveThreadCount(options.threads);
    const std::size_t pixels = static_cast<std::size_t>(capture.width()) * capture.height();
    const double quantum = 1.0 / ((1 << capture.manifest().camera.bits) - 1);

    DecodedScan scan;
    scan.width = capture.width();
    scan.height = capture.height();
    scan.projectorWidth = parameters.width;
    scan.projectorHeight = parameters.height;
    scan.white = capture.image("white");
    scan.black = capture.image("black");
    scan.status.assign(pixels, DecodeStatus::kDecoded);
    scan.direct.assign(pixels, 0.0f);
    scan.global.assign(pixels, 0.0f);

    // Flat frames: where the projector reaches at all, and whether the white frame is usable.
    std::size_t brightEnough = 0, saturated = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        const double contrast = double(scan.white[p]) - double(scan.black[p]);
        if (contrast < options.minDirect) {
            scan.status[p] = DecodeStatus::kDark;
            continue;
        }
        ++brightEnough;
        if (double(scan.white[p]) >= options.saturation) {
            scan.status[p] = DecodeStatus::kSaturated;
            ++saturated;
        }
    }
    const std::filesystem::path whitePath = capture.imagePath(capture.imageIndex("white"));
    if (brightEnough < std::max<std::size_t>(16, pixels / 10000)) {
        throw common::InputError(
            whitePath, "the white frame shows no projector light (white − black < " +
                           std::to_string(options.minDirect) +
                           " everywhere): projector off, lens capped, or exposure too short");
    }
    if (saturated * 2 > brightEnough) {
        throw common::InputError(whitePath,
                                 "saturated in " + std::to_string(100 * saturated / brightEnough) +
                                     "% of the lit pixels: lower the camera's exposure or gain");
    }

    const auto load = [&](const proto::PatternSpec& pattern) {
        return capture.image(capture.imageIndex(pattern.name()));
    };
    const auto pathOf = [&](const proto::PatternSpec& pattern) {
        return capture.imagePath(capture.imageIndex(pattern.name()));
    };
    const int lowest = sequence.lowestGrayBit();
    const proto::PatternAxis axes[2] = {proto::PatternAxis::kColumns, proto::PatternAxis::kRows};

    // The direct light, from the two finest Gray pairs of each axis (high frequencies: the
    // global light is the same under a pattern and its inverse), and the camera's noise from
    // how far each pair's sum departs from white + black.
    std::vector<double> noiseLevel, noiseResidual;
    for (const proto::PatternAxis axis : axes) {
        const int finest = std::min(lowest + 1, sequence.grayBits(axis) - 1);
        for (int bit = lowest; bit <= finest; ++bit) {
            const proto::PatternSpec on{proto::PatternKind::kGray, axis, bit, false, 0};
            const proto::PatternSpec off{proto::PatternKind::kGray, axis, bit, true, 0};
            const std::vector<float> p = load(on), i = load(off);
            for (std::size_t q = 0; q < pixels; ++q) {
                scan.direct[q] = std::max(scan.direct[q], std::abs(p[q] - i[q]));
            }
            if (bit == lowest && axis == proto::PatternAxis::kColumns) {
                for (std::size_t q = 0; q < pixels; q += 3) {
                    if (scan.status[q] == DecodeStatus::kDecoded) {
                        noiseLevel.push_back(double(scan.white[q]) + double(scan.black[q]));
                        noiseResidual.push_back(double(p[q]) + double(i[q]) -
                                                double(scan.white[q]) - double(scan.black[q]));
                    }
                }
            }
        }
    }
    scan.noise = detail::fitNoiseModel(noiseLevel, noiseResidual, quantum);
    for (std::size_t p = 0; p < pixels; ++p) {
        const double contrast = double(scan.white[p]) - double(scan.black[p]);
        scan.global[p] = static_cast<float>(std::max(0.0, contrast - double(scan.direct[p])));
        if (scan.status[p] == DecodeStatus::kDecoded &&
            double(scan.direct[p]) < options.minDirect) {
            scan.status[p] = DecodeStatus::kDark;  // lit, but only by the room or by bounces
        }
    }
    const std::vector<std::size_t> lit = litPixels(scan);
    const auto margin = [&](std::size_t p) {
        return options.noiseSigmas * std::sqrt(2.0) * scan.noise.sigma(scan.white[p]) +
               options.relativeMargin * (double(scan.white[p]) - double(scan.black[p]));
    };

    // A pattern and its inverse must add up to white + black wherever the projector reaches:
    // a pair that does not was captured wrong (a black frame, a stale one, a clipped one).
    const auto checkPair = [&](const std::vector<float>& p, const std::vector<float>& i,
                               const proto::PatternSpec& on, const proto::PatternSpec& off) {
        std::vector<double> ratio;
        for (std::size_t k = 0; k < lit.size(); k += 7) {
            const std::size_t q = lit[k];
            const double contrast = double(scan.white[q]) - double(scan.black[q]);
            ratio.push_back(
                (double(p[q]) + double(i[q]) - double(scan.white[q]) - double(scan.black[q])) /
                contrast);
        }
        const double m = common::quantile(ratio, 0.5);
        if (std::abs(m) > kFrameTolerance) {
            // The frame that departs from its own expectation most is the wrong one.
            double darkP = 0, darkI = 0;
            for (std::size_t k = 0; k < lit.size(); k += 7) {
                darkP += double(p[lit[k]]);
                darkI += double(i[lit[k]]);
            }
            const bool blame = m < 0 ? darkP < darkI : darkP > darkI;
            throw common::InputError(
                blame ? pathOf(on) : pathOf(off),
                std::string(m < 0 ? "black or stale" : "saturated or stale") +
                    ": with its inverse it adds up to " +
                    std::to_string(static_cast<int>(std::lround(100 * (1 + m)))) +
                    "% of white + black, not 100% (pattern '" + (blame ? on : off).name() + "')");
        }
    };

    AxisState state[2];
    for (int a = 0; a < 2; ++a) {
        const proto::PatternAxis axis = axes[a];
        AxisState& s = state[a];
        s.code.assign(pixels, 0);
        s.uncertain.assign(pixels, kNoUncertainBit);
        s.sine.assign(pixels, 0.0f);
        s.cosine.assign(pixels, 0.0f);
        for (int bit = sequence.grayBits(axis) - 1; bit >= lowest; --bit) {
            const proto::PatternSpec on{proto::PatternKind::kGray, axis, bit, false, 0};
            const proto::PatternSpec off{proto::PatternKind::kGray, axis, bit, true, 0};
            const std::vector<float> p = load(on), i = load(off);
            checkPair(p, i, on, off);
            const std::uint32_t weight = 1u << (bit - lowest);
            common::parallelFor(
                lit.size(), kGrain, threads, [&](std::size_t begin, std::size_t end) {
                    for (std::size_t k = begin; k < end; ++k) {
                        const std::size_t q = lit[k];
                        const double pl = double(p[q]) - double(scan.black[q]);
                        const double il = double(i[q]) - double(scan.black[q]);
                        const double d = scan.direct[q], g = scan.global[q], tau = margin(q);
                        // p = d·x + g_p, i = d·(1 − x) + g_i with 0 ≤ g_p, g_i ≤ g: a value above
                        // g can only be direct light, one below d cannot hold it.
                        const bool one = pl > g + tau || il < d - tau;
                        const bool zero = il > g + tau || pl < d - tau;
                        if (one != zero) {
                            s.code[q] |= one ? weight : 0u;
                            continue;
                        }
                        // Undecided: at a stripe's edge (both half lit) or drowned in global light.
                        // One per axis is allowed, and settled by the phase below.
                        s.code[q] |= pl > il ? weight : 0u;
                        s.uncertain[q] = s.uncertain[q] == kNoUncertainBit
                                             ? static_cast<std::int8_t>(bit - lowest)
                                             : static_cast<std::int8_t>(kTooManyUncertainBits);
                    }
                });
        }
        for (int step = 0; step < parameters.phaseSteps; ++step) {
            const proto::PatternSpec pattern{proto::PatternKind::kPhase, axis, 0, false, step};
            const std::vector<float> image = load(pattern);
            std::vector<double> share;
            for (std::size_t k = 0; k < lit.size(); k += 7) {
                const std::size_t q = lit[k];
                share.push_back((double(image[q]) - double(scan.black[q])) /
                                (double(scan.white[q]) - double(scan.black[q])));
            }
            const double m = common::quantile(share, 0.5);
            if (!(m > 0.02 && m < 0.98)) {
                throw common::InputError(
                    pathOf(pattern), std::string(m <= 0.02 ? "black" : "saturated") +
                                         ": its lit pixels hold " +
                                         std::to_string(static_cast<int>(std::lround(100 * m))) +
                                         "% of white − black (pattern '" + pattern.name() + "')");
            }
            const double delta = 2 * kPi * step / parameters.phaseSteps;
            const auto c = static_cast<float>(std::cos(delta)),
                       sn = static_cast<float>(std::sin(delta));
            for (const std::size_t q : lit) {
                s.sine[q] += image[q] * sn;
                s.cosine[q] += image[q] * c;
            }
        }
    }

    scan.projectorX.assign(pixels, kNaN);
    scan.projectorY.assign(pixels, kNaN);
    scan.precision.assign(pixels, kNaN);
    const double period = parameters.phasePeriod;
    const double binWidth = sequence.grayBinWidth();
    const double steps = parameters.phaseSteps;
    common::parallelFor(lit.size(), kGrain, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t q = lit[k];
            double position[2] = {0, 0}, worst = 0;
            DecodeStatus status = DecodeStatus::kDecoded;
            for (int a = 0; a < 2 && status == DecodeStatus::kDecoded; ++a) {
                const AxisState& s = state[a];
                const int extent = a == 0 ? parameters.width : parameters.height;
                if (s.uncertain[q] == kTooManyUncertainBits) {
                    status = DecodeStatus::kAmbiguous;
                    break;
                }
                const double amplitude =
                    2.0 / steps * std::hypot(double(s.sine[q]), double(s.cosine[q]));
                if (amplitude < options.minModulation * double(scan.direct[q])) {
                    status = DecodeStatus::kLowModulation;
                    break;
                }
                double angle = std::atan2(double(s.sine[q]), double(s.cosine[q]));
                if (angle < 0) {
                    angle += 2 * kPi;
                }
                const double inPeriod = angle / (2 * kPi) * period;
                // The candidates: the code as read, and with the undecided bit flipped when the
                // two codes are neighbours (an edge between two bins); the phase picks.
                std::uint32_t candidates[2] = {s.code[q], s.code[q]};
                int count = 1;
                if (s.uncertain[q] >= 0) {
                    candidates[1] ^= 1u << s.uncertain[q];
                    const auto b0 = static_cast<long>(proto::grayDecode(candidates[0]));
                    const auto b1 = static_cast<long>(proto::grayDecode(candidates[1]));
                    if (std::abs(b0 - b1) != 1) {
                        status = DecodeStatus::kAmbiguous;
                        break;
                    }
                    count = 2;
                }
                double best = std::numeric_limits<double>::infinity(), chosen = 0;
                for (int c = 0; c < count; ++c) {
                    const double bin = proto::grayDecode(candidates[c]);
                    const double coarse = bin * binWidth + (binWidth - 1) / 2;
                    const double turns = std::round((coarse - inPeriod) / period);
                    const double x = inPeriod + turns * period;
                    if (std::abs(x - coarse) < best) {
                        best = std::abs(x - coarse);
                        chosen = x;
                    }
                }
                // Inside its bin the phase sits within half a bin of the bin's centre; an edge
                // read on the wrong side adds one bin.
                if (best > 1.5 * binWidth || chosen < -0.5 || chosen > extent - 0.5) {
                    status = DecodeStatus::kInconsistent;
                    break;
                }
                position[a] = chosen;
                // σ(θ) = σ_I·√(2/N)/A for N steps of amplitude A; the noise at the mean level.
                const double sigmaI =
                    scan.noise.sigma(0.5 * (double(scan.white[q]) + double(scan.black[q])));
                worst = std::max(worst,
                                 period / (2 * kPi) * sigmaI * std::sqrt(2.0 / steps) / amplitude);
                if (worst > options.maxSigma) {
                    status = DecodeStatus::kLowModulation;
                }
            }
            scan.status[q] = status;
            if (status == DecodeStatus::kDecoded) {
                scan.projectorX[q] = static_cast<float>(position[0]);
                scan.projectorY[q] = static_cast<float>(position[1]);
                scan.precision[q] = static_cast<float>(worst);
            }
        }
    });
    detail::markMixedPixels(scan, options.maxBend, threads);
    detail::countStatuses(scan, lit.size());
    return scan;
}

}  // namespace vpe::structured_light
