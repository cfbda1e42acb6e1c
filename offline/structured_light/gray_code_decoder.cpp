// SPDX-License-Identifier: MIT
// A Gray code without phase images (OpenCV's GrayCodePattern, as other tools capture it),
// decoded per camera pixel to whole Gray bins. Each bit is read from its pair's difference
// against the camera noise at the pair's level: a noisy camera costs precision, never a pixel
// whose code is certain. White and black are used where they were shown; where not, each
// pair's mean and range stand in.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"

#include "decoding_steps.h"

namespace vpe::structured_light::detail {

namespace {

// A pair whose sum misses the reference's (white + black, or the first pair's) by half the direct
// light on more than this share of the lit pixels was captured wrong: black, stale or clipped.
constexpr double kWrongFrameShare = 0.1;

struct GrayPair {
    proto::PatternSpec on, off;
    int axis = 0;  // 0: columns, 1: rows
};

// Every shown pair, the columns' from the most significant bit, then the rows'.
std::vector<GrayPair> grayPairs(const proto::StructuredLightSequence& sequence) {
    std::vector<GrayPair> pairs;
    for (const proto::PatternSpec& pattern : sequence.patterns()) {
        if (pattern.kind == proto::PatternKind::kGray && !pattern.inverted) {
            proto::PatternSpec inverse = pattern;
            inverse.inverted = true;
            pairs.push_back(
                {pattern, inverse, pattern.axis == proto::PatternAxis::kColumns ? 0 : 1});
        }
    }
    return pairs;
}

}  // namespace

DecodedScan decodeGrayCode(const ScanCapture& capture, const DecodeOptions& options) {
    const proto::StructuredLightSequence& sequence = capture.sequence();
    const proto::StructuredLightParameters& parameters = sequence.parameters();
    const unsigned threads = common::resolveThreadCount(options.threads);
    const std::size_t pixels = static_cast<std::size_t>(capture.width()) * capture.height();
    const double quantum = 1.0 / ((1 << capture.manifest().camera.bits) - 1);
    const bool flats = parameters.flatFields;
    const std::vector<GrayPair> pairs = grayPairs(sequence);
    const auto load = [&](const proto::PatternSpec& pattern) {
        return capture.image(capture.imageIndex(pattern.name()));
    };
    const auto pathOf = [&](const proto::PatternSpec& pattern) {
        return capture.imagePath(capture.imageIndex(pattern.name()));
    };

    DecodedScan scan;
    scan.width = capture.width();
    scan.height = capture.height();
    scan.projectorWidth = parameters.width;
    scan.projectorHeight = parameters.height;
    scan.status.assign(pixels, DecodeStatus::kDecoded);
    scan.direct.assign(pixels, 0.0f);
    scan.global.assign(pixels, 0.0f);

    // The reference every pair's sum is checked against, and the noise measured on: white +
    // black, or without them the first pair (the coarsest columns: its stripes are crisp, so its
    // sum is the full light's even through a camera's curve).
    std::vector<float> first = load(pairs[0].on), firstInverse = load(pairs[0].off);
    std::vector<float> referenceSum(pixels), referenceRange(pixels);
    if (flats) {
        scan.white = capture.image("white");
        scan.black = capture.image("black");
    } else {
        scan.white.assign(pixels, -std::numeric_limits<float>::infinity());
        scan.black.assign(pixels, std::numeric_limits<float>::infinity());
    }
    for (std::size_t q = 0; q < pixels; ++q) {
        referenceSum[q] = flats ? scan.white[q] + scan.black[q] : first[q] + firstInverse[q];
        referenceRange[q] =
            flats ? scan.white[q] - scan.black[q] : std::abs(first[q] - firstInverse[q]);
    }
    std::vector<std::size_t> sampled;  // lit by the reference: every 3rd pixel
    for (std::size_t q = 0; q < pixels; q += 3) {
        if (double(referenceRange[q]) >= options.minDirect) {
            sampled.push_back(q);
        }
    }
    const std::filesystem::path referencePath =
        flats ? capture.imagePath(capture.imageIndex("white")) : pathOf(pairs[0].on);
    if (sampled.size() * 3 < std::max<std::size_t>(16, pixels / 10000)) {
        throw common::InputError(
            referencePath, std::string("shows no projector light (") +
                               (flats ? "white − black" : "the pattern against its inverse") +
                               " < " + std::to_string(options.minDirect) +
                               " everywhere): projector off, lens capped, or exposure too short");
    }

    // The camera's noise: p + i − W − B on the first pair, or without flat fields the first
    // pair's sum against the second's (pairs.size() ≥ 2: each axis shows a bit at least).
    std::vector<float> second, secondInverse;  // kept for the loop below
    {
        std::vector<double> level, residual;
        if (!flats) {
            second = load(pairs[1].on);
            secondInverse = load(pairs[1].off);
        }
        for (const std::size_t q : sampled) {
            const double sum = double(first[q]) + double(firstInverse[q]);
            const double other =
                flats ? double(referenceSum[q]) : double(second[q]) + double(secondInverse[q]);
            level.push_back(flats ? other : (sum + other) / 2);
            residual.push_back(sum - other);
        }
        scan.noise = fitNoiseModel(level, residual, quantum);
    }

    AxisCode axes[2];
    for (AxisCode& axis : axes) {
        axis.code.assign(pixels, 0);
        axis.uncertain.assign(pixels, kNoUncertainBit);
    }
    const int lowest = sequence.lowestGrayBit();
    const double sigmas = options.noiseSigmas;
    const NoiseModel noise = scan.noise;
    for (std::size_t n = 0; n < pairs.size(); ++n) {
        const GrayPair& pair = pairs[n];
        std::vector<float> p = n == 0             ? std::move(first)
                               : n == 1 && !flats ? std::move(second)
                                                  : load(pair.on);
        std::vector<float> i = n == 0             ? std::move(firstInverse)
                               : n == 1 && !flats ? std::move(secondInverse)
                                                  : load(pair.off);
        if (flats || n > 0) {
            // A pattern and its inverse add up to the reference wherever the projector reaches.
            // A black or stale frame leaves the pixels its pattern should light short by the
            // whole direct light, a clipped or stale one over: counted where the sum misses by
            // half of it (a stripe's edge or the noise stays well inside).
            std::size_t shortBy = 0, overBy = 0, count = 0;
            double sumP = 0, sumI = 0;
            for (std::size_t k = 0; k < sampled.size(); k += 3, ++count) {
                const std::size_t q = sampled[k];
                const double departure = (double(p[q]) + double(i[q]) - double(referenceSum[q])) /
                                         double(referenceRange[q]);
                shortBy += departure < -0.5 ? 1 : 0;
                overBy += departure > 0.5 ? 1 : 0;
                sumP += double(p[q]);
                sumI += double(i[q]);
            }
            const std::size_t worse = std::max(shortBy, overBy);
            if (worse > kWrongFrameShare * static_cast<double>(count)) {
                const bool dark = shortBy >= overBy;
                const bool blameOn = dark ? sumP < sumI : sumP > sumI;
                const proto::PatternSpec& blamed = blameOn ? pair.on : pair.off;
                throw common::InputError(
                    pathOf(blamed),
                    std::string(dark ? "black or stale" : "saturated or stale") +
                        ": with its inverse it " + (dark ? "falls short of " : "exceeds ") +
                        (flats ? "white + black" : "the first pair's sum") +
                        " by half the direct light or more on " +
                        std::to_string(100 * worse / std::max<std::size_t>(count, 1)) +
                        "% of the lit pixels (pattern '" + blamed.name() + "')");
            }
        }
        AxisCode& axis = axes[pair.axis];
        const std::uint32_t weight = 1u << (pair.on.bit - lowest);
        const auto uncertainMark = static_cast<std::int8_t>(pair.on.bit - lowest);
        common::parallelFor(pixels, kGrain, threads, [&](std::size_t begin, std::size_t end) {
            for (std::size_t q = begin; q < end; ++q) {
                const double on = double(p[q]), off = double(i[q]), difference = on - off;
                scan.direct[q] = std::max(scan.direct[q], static_cast<float>(std::abs(difference)));
                if (!flats) {
                    scan.white[q] = std::max({scan.white[q], p[q], i[q]});
                    scan.black[q] = std::min({scan.black[q], p[q], i[q]});
                }
                // var(p − i) = σ²(p) + σ²(i) = 2a + b·(p + i): the noise at this pair's level.
                const double spread = std::sqrt(
                    std::max(0.0, 2 * noise.constant + noise.perSignal * std::max(on + off, 0.0)));
                axis.code[q] |= difference > 0 ? weight : 0u;
                if (std::abs(difference) <= sigmas * spread) {
                    // Too close to call: a stripe's edge falls inside the pixel, or the light
                    // here is too weak. One per axis is an edge between two bins; more drop it.
                    axis.uncertain[q] = axis.uncertain[q] == kNoUncertainBit
                                            ? uncertainMark
                                            : static_cast<std::int8_t>(kTooManyUncertainBits);
                }
            }
        });
    }

    scan.projectorX.assign(pixels, kNaN);
    scan.projectorY.assign(pixels, kNaN);
    scan.precision.assign(pixels, kNaN);
    scan.source.assign(pixels, PositionSource::kNone);
    const double binWidth = sequence.grayBinWidth();
    // A whole bin's position is uniform across its width: σ = width / √12.
    const auto precision = static_cast<float>(binWidth / std::sqrt(12.0));
    const int extents[2] = {parameters.width, parameters.height};
    std::size_t lit = 0;
    for (std::size_t q = 0; q < pixels; ++q) {
        const double range = double(scan.white[q]) - double(scan.black[q]);
        scan.global[q] = static_cast<float>(std::max(0.0, range - double(scan.direct[q])));
        if ((flats && range < options.minDirect) || double(scan.direct[q]) < options.minDirect) {
            scan.status[q] = DecodeStatus::kDark;
            continue;
        }
        ++lit;
        double position[2] = {0, 0};
        DecodeStatus status = DecodeStatus::kDecoded;
        for (int a = 0; a < 2 && status == DecodeStatus::kDecoded; ++a) {
            const AxisCode& axis = axes[a];
            const std::int8_t openBit = axis.uncertain[q];
            const auto bin = static_cast<double>(proto::grayDecode(axis.code[q]));
            if (openBit == kTooManyUncertainBits) {
                status = DecodeStatus::kAmbiguous;
            } else if (openBit == kNoUncertainBit) {
                // The bin's centre; the last bin may be cut short by the projector's edge.
                const double start = bin * binWidth;
                position[a] = (start + std::min(start + binWidth, double(extents[a])) - 1) / 2;
                if (start >= extents[a]) {
                    status = DecodeStatus::kInconsistent;  // a code the projector does not have
                }
            } else {
                // The open bit either way: two neighbouring bins put the pixel on the edge
                // between them; any other pair of codes is no edge the pixel can be on.
                const auto other = static_cast<double>(
                    proto::grayDecode(axis.code[q] ^ (1u << static_cast<unsigned>(openBit))));
                const double edge = std::max(bin, other) * binWidth;
                position[a] = edge - 0.5;
                if (std::abs(bin - other) != 1) {
                    status = DecodeStatus::kAmbiguous;
                } else if (edge >= extents[a]) {
                    status = DecodeStatus::kInconsistent;
                }
            }
        }
        scan.status[q] = status;
        if (status == DecodeStatus::kDecoded) {
            scan.projectorX[q] = static_cast<float>(position[0]);
            scan.projectorY[q] = static_cast<float>(position[1]);
            scan.precision[q] = precision;
            scan.source[q] = PositionSource::kGrayBin;
        }
    }
    checkCodesFitTheProjector(capture, axes[0], axes[1], scan.status);
    // Whole bins step by a bin between neighbours where the surface is smooth: a step between
    // surfaces must bend the coordinates by more than two bins' rounding.
    markMixedPixels(scan, options.maxBend, binWidth, threads);
    countStatuses(scan, lit);
    return scan;
}

}  // namespace vpe::structured_light::detail
