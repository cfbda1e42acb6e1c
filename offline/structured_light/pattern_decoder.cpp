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

// The largest neighbourhood the phase is summed over (5 × 5), and how bright against the object's
// median direct light a pixel must be for its neighbours to help.
constexpr int kLargestRadius = 2;
constexpr double kNoisyButBright = 0.25;
// The decoded phase's histogram over the object's brighter pixels: this many bins, and the
// largest departure of a bin from the mean count (a share) beyond which the phase is distorted
// (clean captures: at most 0.19; a DLP caught by a 1.5-frame exposure 0.34, by 0.3 frames 2.6),
// or 4.5 times a bin's statistical spread where fewer pixels make it noisier.
constexpr int kPhaseBins = 32;
constexpr double kDistortedPhase = 0.25;
// ... and the equalization is kept where it brings the pixels on Gray edges closer to them (RMS,
// by 5 % at least). Measured, before → after: a DLP at 0.3 frames 0.42 → 0.23 and 0.79 → 0.32
// px; at 0.5 frames 0.47 → 0.22 and 0.38 → 0.33; a 50° concave corner 0.32 → 0.82 (its own
// uneven phase, not a distortion).
constexpr double kEqualizationGain = 0.95;
// The pair's difference decides a bit only where the global light is this small a share of the
// direct: the finest pairs' estimate of it misses a concave corner's mirror-like bounce, which
// can flip a difference that clears it.
constexpr double kLittleGlobal = 0.1;
// settleByNeighbours' verdict: the bit settled, and to one (above any bit's weight).
constexpr std::uint32_t kSettledOne = 1u << 31;

// A frame whose median over the lit pixels sits this far from where it must (its pair's sum, or
// inside white and black) was captured wrong: black (the camera missed it) or saturated.
constexpr double kFrameTolerance = 0.4;

// The Gray bits read so far, and Σ I_s sin δ_s, Σ I_s cos δ_s over the phase shifts.
struct AxisState : detail::AxisCode {
    std::vector<float> sine, cosine;
    // Per pixel, the bits its own pair left open, and those of them its neighbours settled.
    std::vector<std::uint32_t> open, settled;
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

// One axis of one pixel, placed.
struct AxisPosition {
    DecodeStatus status = DecodeStatus::kDecoded;
    PositionSource source = PositionSource::kNone;
    double position = 0, sigma = 0;
};

// The stages of decoding a Gray code with phase shifting, in the order decode() runs them.
class PhaseShiftDecoder {
public:
    PhaseShiftDecoder(const ScanCapture& capture, const DecodeOptions& options)
        : capture_(capture),
          options_(options),
          sequence_(capture.sequence()),
          parameters_(sequence_.parameters()),
          threads_(common::resolveThreadCount(options.threads)),
          pixels_(static_cast<std::size_t>(capture.width()) * capture.height()) {}

    DecodedScan decode() {
        readFlatFields();
        measureDirectLight();
        for (int a = 0; a < 2; ++a) {
            readGrayBits(a);
        }
        detail::checkCodesFitTheProjector(capture_, state_[0], state_[1], scan_.status);
        for (int a = 0; a < 2; ++a) {
            accumulatePhase(a);
        }
        for (int a = 0; a < 2; ++a) {
            equalizePhase(a);
        }
        placePixels();
        // Gray bins are period / 4 wide: a bend through one placed by its bin may be that much.
        detail::markMixedPixels(scan_, options_.maxBend, sequence_.grayBinWidth(), threads_);
        detail::countStatuses(scan_, lit_.size());
        return std::move(scan_);
    }

private:
    static constexpr proto::PatternAxis kAxes[2] = {proto::PatternAxis::kColumns,
                                                    proto::PatternAxis::kRows};

    // An image as the camera's signal (its encoding undone).
    std::vector<float> load(const proto::PatternSpec& pattern) const {
        std::vector<float> values = capture_.image(capture_.imageIndex(pattern.name()));
        detail::linearize(values, scan_.cameraGamma);
        return values;
    }
    std::filesystem::path pathOf(const proto::PatternSpec& pattern) const {
        return capture_.imagePath(capture_.imageIndex(pattern.name()));
    }
    static proto::PatternSpec grayPattern(proto::PatternAxis axis, int bit, bool inverted) {
        return {proto::PatternKind::kGray, axis, bit, inverted, 0};
    }

    void readFlatFields();
    void measureDirectLight();
    void checkPair(const std::vector<float>& p, const std::vector<float>& i,
                   const proto::PatternSpec& on, const proto::PatternSpec& off) const;
    void readGrayBits(int a);
    // A Gray pair's difference p − i at one pixel (or summed over several), its noise variance,
    // and the global and direct light under it.
    struct PairDifference {
        double difference = 0, variance = 0, global = 0, direct = 0;
    };
    PairDifference pairDifference(const std::vector<float>& p, const std::vector<float>& i,
                                  std::size_t q) const;
    bool settlesTheBit(const PairDifference& pair) const;
    void settleByNeighbours(int a, int bit, const std::vector<float>& p,
                            const std::vector<float>& i);
    void markUncertainBits(int a);
    void accumulatePhase(int a);
    AxisPosition placeAxis(int a, std::size_t q, const std::vector<std::uint8_t>& isLit) const;
    AxisPosition placeByGrayBin(int a, std::size_t q) const;
    void placePixels();
    void equalizePhase(int a);
    // The phase as decoded mapped to the phase (radians in [0, 2π)): axis `a`'s equalization,
    // or the identity.
    double correctedPhase(int a, double angle) const;

    // The noise margin of the bit tests at pixel q.
    double margin(std::size_t q) const {
        return options_.noiseSigmas * std::sqrt(2.0) * scan_.noise.sigma(scan_.white[q]) +
               options_.relativeMargin * (double(scan_.white[q]) - double(scan_.black[q]));
    }

    const ScanCapture& capture_;
    const DecodeOptions& options_;
    const proto::StructuredLightSequence& sequence_;
    const proto::StructuredLightParameters& parameters_;
    const unsigned threads_;
    const std::size_t pixels_;
    DecodedScan scan_;
    std::vector<std::size_t> lit_;  // the pixels the projector's direct light reaches
    double typicalDirect_ = 0;      // their median direct light
    AxisState state_[2];
    // Per axis: the decoded phase's cumulative distribution at kPhaseBins + 1 edges, and the
    // offset the Gray code sets; empty where the phase is not distorted.
    std::vector<double> phaseCdf_[2];
    double phaseOffset_[2] = {0, 0};
};

// Flat frames: the camera's encoding, where the projector reaches at all, and whether the white
// frame is usable.
void PhaseShiftDecoder::readFlatFields() {
    scan_.width = capture_.width();
    scan_.height = capture_.height();
    scan_.projectorWidth = parameters_.width;
    scan_.projectorHeight = parameters_.height;
    scan_.white = capture_.image("white");
    scan_.black = capture_.image("black");
    scan_.status.assign(pixels_, DecodeStatus::kDecoded);
    scan_.direct.assign(pixels_, 0.0f);
    scan_.global.assign(pixels_, 0.0f);

    // Saturation on the codes as captured: a clipped code is clipped in any encoding.
    std::vector<std::uint8_t> clipped(pixels_, 0);
    for (std::size_t p = 0; p < pixels_; ++p) {
        clipped[p] = double(scan_.white[p]) >= options_.saturation ? 1 : 0;
    }
    // The finest column pair's stripe edges tell the camera's curve.
    {
        const int lowest = sequence_.lowestGrayBit();
        const proto::PatternAxis columns = proto::PatternAxis::kColumns;
        const std::vector<float> on = capture_.image(capture_.imageIndex(
                                     grayPattern(columns, lowest, false).name())),
                                 off = capture_.image(capture_.imageIndex(
                                     grayPattern(columns, lowest, true).name()));
        scan_.cameraGamma = detail::fitCameraGamma(scan_.white, scan_.black, on, off);
    }
    detail::linearize(scan_.white, scan_.cameraGamma);
    detail::linearize(scan_.black, scan_.cameraGamma);

    std::size_t brightEnough = 0, saturated = 0;
    for (std::size_t p = 0; p < pixels_; ++p) {
        const double contrast = double(scan_.white[p]) - double(scan_.black[p]);
        if (contrast < options_.minDirect) {
            scan_.status[p] = DecodeStatus::kDark;
            continue;
        }
        ++brightEnough;
        if (clipped[p]) {
            scan_.status[p] = DecodeStatus::kSaturated;
            ++saturated;
        }
    }
    const std::filesystem::path whitePath = capture_.imagePath(capture_.imageIndex("white"));
    if (brightEnough < std::max<std::size_t>(16, pixels_ / 10000)) {
        throw common::InputError(
            whitePath, "the white frame shows no projector light (white − black < " +
                           std::to_string(options_.minDirect) +
                           " everywhere): projector off, lens capped, or exposure too short");
    }
    if (saturated * 2 > brightEnough) {
        throw common::InputError(whitePath,
                                 "saturated in " + std::to_string(100 * saturated / brightEnough) +
                                     "% of the lit pixels: lower the camera's exposure or gain");
    }
}

// The direct light, from the two finest Gray pairs of each axis (high frequencies: the global
// light is the same under a pattern and its inverse), and the camera's noise from how far each
// pair's sum departs from white + black. A pixel is lit where the direct light stands above
// minDirect and above what the noise alone makes of |pattern − inverse|.
void PhaseShiftDecoder::measureDirectLight() {
    const int lowest = sequence_.lowestGrayBit();
    std::vector<double> noiseLevel, noiseResidual;
    for (const proto::PatternAxis axis : kAxes) {
        const int finest = std::min(lowest + 1, sequence_.grayBits(axis) - 1);
        for (int bit = lowest; bit <= finest; ++bit) {
            const std::vector<float> p = load(grayPattern(axis, bit, false)),
                                     i = load(grayPattern(axis, bit, true));
            for (std::size_t q = 0; q < pixels_; ++q) {
                scan_.direct[q] = std::max(scan_.direct[q], std::abs(p[q] - i[q]));
            }
            if (bit == lowest && axis == proto::PatternAxis::kColumns) {
                for (std::size_t q = 0; q < pixels_; q += 3) {
                    if (scan_.status[q] == DecodeStatus::kDecoded) {
                        noiseLevel.push_back(double(scan_.white[q]) + double(scan_.black[q]));
                        noiseResidual.push_back(double(p[q]) + double(i[q]) -
                                                double(scan_.white[q]) - double(scan_.black[q]));
                    }
                }
            }
        }
    }
    // The camera's step, in signal: an encoding's steepest step is γ codes' worth.
    const double quantum = scan_.cameraGamma / ((1 << capture_.manifest().camera.bits) - 1);
    scan_.noise = detail::fitNoiseModel(noiseLevel, noiseResidual, quantum);
    for (std::size_t p = 0; p < pixels_; ++p) {
        const double contrast = double(scan_.white[p]) - double(scan_.black[p]);
        scan_.global[p] = static_cast<float>(std::max(0.0, contrast - double(scan_.direct[p])));
        // |p − i| of an unlit pixel is noise of σ√2 at the black level: the largest of four
        // such reaches a few σ.
        const double noiseFloor =
            options_.noiseSigmas * std::sqrt(2.0) * scan_.noise.sigma(scan_.black[p]);
        if (scan_.status[p] == DecodeStatus::kDecoded &&
            double(scan_.direct[p]) < options_.minDirect + noiseFloor) {
            scan_.status[p] = DecodeStatus::kDark;  // lit, but only by the room or by bounces
        }
    }
    lit_ = litPixels(scan_);
    std::vector<double> direct;
    for (std::size_t k = 0; k < lit_.size(); k += 7) {
        direct.push_back(double(scan_.direct[lit_[k]]));
    }
    typicalDirect_ = direct.empty() ? 0.0 : common::quantile(direct, 0.5);
}

// A pattern and its inverse must add up to white + black wherever the projector reaches: a pair
// that does not was captured wrong (a black frame, a stale one, a clipped one).
void PhaseShiftDecoder::checkPair(const std::vector<float>& p, const std::vector<float>& i,
                                  const proto::PatternSpec& on,
                                  const proto::PatternSpec& off) const {
    std::vector<double> ratio;
    for (std::size_t k = 0; k < lit_.size(); k += 7) {
        const std::size_t q = lit_[k];
        const double contrast = double(scan_.white[q]) - double(scan_.black[q]);
        ratio.push_back(
            (double(p[q]) + double(i[q]) - double(scan_.white[q]) - double(scan_.black[q])) /
            contrast);
    }
    const double m = common::quantile(ratio, 0.5);
    if (std::abs(m) > kFrameTolerance) {
        // The frame that departs from its own expectation most is the wrong one.
        double darkP = 0, darkI = 0;
        for (std::size_t k = 0; k < lit_.size(); k += 7) {
            darkP += double(p[lit_[k]]);
            darkI += double(i[lit_[k]]);
        }
        const bool blame = m < 0 ? darkP < darkI : darkP > darkI;
        throw common::InputError(blame ? pathOf(on) : pathOf(off),
                                 std::string(m < 0 ? "black or stale" : "saturated or stale") +
                                     ": with its inverse it adds up to " +
                                     std::to_string(static_cast<int>(std::lround(100 * (1 + m)))) +
                                     "% of white + black, not 100% (pattern '" +
                                     (blame ? on : off).name() + "')");
    }
}

// The Gray bits of axis `a`, most significant first. A bit is read where Xu and Aliaga's test
// finds it in the direct light alone, or where the pair's difference exceeds all the global light
// and the camera's noise could make of it; else it is open. One open bit per axis is an edge
// between two bins (the phase, or the bins' edge, places the pixel); where the noise leaves more
// open, the pixel's 3 × 3 neighbourhood settles them (settleByNeighbours).
void PhaseShiftDecoder::readGrayBits(int a) {
    const proto::PatternAxis axis = kAxes[a];
    AxisState& s = state_[a];
    s.code.assign(pixels_, 0);
    s.open.assign(pixels_, 0);
    s.settled.assign(pixels_, 0);
    const int lowest = sequence_.lowestGrayBit();
    for (int bit = sequence_.grayBits(axis) - 1; bit >= lowest; --bit) {
        const proto::PatternSpec on = grayPattern(axis, bit, false),
                                 off = grayPattern(axis, bit, true);
        const std::vector<float> p = load(on), i = load(off);
        checkPair(p, i, on, off);
        const std::uint32_t weight = 1u << (bit - lowest);
        common::parallelFor(lit_.size(), kGrain, threads_, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const std::size_t q = lit_[k];
                const double pl = double(p[q]) - double(scan_.black[q]);
                const double il = double(i[q]) - double(scan_.black[q]);
                const double d = scan_.direct[q], g = scan_.global[q], tau = margin(q);
                // p = d·x + g_p, i = d·(1 − x) + g_i with 0 ≤ g_p, g_i ≤ g: a value above g can
                // only be direct light, one below d cannot hold it.
                const bool one = pl > g + tau || il < d - tau;
                const bool zero = il > g + tau || pl < d - tau;
                if (one != zero) {
                    s.code[q] |= one ? weight : 0u;
                    continue;
                }
                const PairDifference pair = pairDifference(p, i, q);
                s.code[q] |= pair.difference > 0 ? weight : 0u;
                if (!settlesTheBit(pair)) {
                    // Undecided: at a stripe's edge (both half lit) or drowned in global light
                    // or noise.
                    s.open[q] |= weight;
                }
            }
        });
        settleByNeighbours(a, bit, p, i);
    }
    markUncertainBits(a);
}

// p − i = d·(2x − 1) + g_p − g_i, and |g_p − g_i| ≤ g: a difference beyond g and the noise of
// var(p − i) = 2a + b·(p + i) has the direct light's sign.
PhaseShiftDecoder::PairDifference PhaseShiftDecoder::pairDifference(const std::vector<float>& p,
                                                                    const std::vector<float>& i,
                                                                    std::size_t q) const {
    const NoiseModel& noise = scan_.noise;
    PairDifference pair;
    pair.difference = double(p[q]) - double(i[q]);
    pair.variance = std::max(
        0.0, 2 * noise.constant + noise.perSignal * std::max(double(p[q]) + double(i[q]), 0.0));
    pair.global = scan_.global[q];
    pair.direct = scan_.direct[q];
    return pair;
}

bool PhaseShiftDecoder::settlesTheBit(const PairDifference& pair) const {
    return pair.global < kLittleGlobal * pair.direct &&
           std::abs(pair.difference) >
               2 * pair.global + options_.noiseSigmas * std::sqrt(pair.variance);
}

// A bit the noise left open at a pixel is, away from its stripe's edge, the bit its neighbours
// show too: their differences add, the noise only as its square root (a 3 × 3 sum is 3 times
// surer). Neighbours count where lit and on the same stripes so far (their coarser bits the
// pixel's), so a silhouette's other surface does not outvote it; at the stripe's own edge the
// sum cancels and leaves the bit open, or sides with the majority, one bin away, which the
// phase's unwrapping (half a period = two bins) absorbs.
void PhaseShiftDecoder::settleByNeighbours(int a, int bit, const std::vector<float>& p,
                                           const std::vector<float>& i) {
    AxisState& s = state_[a];
    const int lowest = sequence_.lowestGrayBit();
    const std::uint32_t weight = 1u << (bit - lowest);
    const std::uint32_t coarser = ~((weight << 1) - 1);
    const int w = scan_.width, h = scan_.height;
    std::vector<std::uint32_t> verdict(pixels_, 0);
    common::parallelFor(lit_.size(), kGrain, threads_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t q = lit_[k];
            if ((s.open[q] & weight) == 0) {
                continue;
            }
            const int x = static_cast<int>(q % static_cast<std::size_t>(w));
            const int y = static_cast<int>(q / static_cast<std::size_t>(w));
            PairDifference sum;
            for (int v = std::max(0, y - 1); v <= std::min(h - 1, y + 1); ++v) {
                for (int u = std::max(0, x - 1); u <= std::min(w - 1, x + 1); ++u) {
                    const std::size_t r = static_cast<std::size_t>(v) * w + u;
                    if (scan_.status[r] != DecodeStatus::kDecoded ||
                        (s.code[r] & coarser) != (s.code[q] & coarser)) {
                        continue;
                    }
                    const PairDifference one = pairDifference(p, i, r);
                    sum.difference += one.difference;
                    sum.variance += one.variance;
                    sum.global += one.global;
                    sum.direct += one.direct;
                }
            }
            if (settlesTheBit(sum)) {
                verdict[q] = weight | (sum.difference > 0 ? kSettledOne : 0u);
            }
        }
    });
    for (const std::size_t q : lit_) {
        if (verdict[q] != 0) {
            s.settled[q] |= weight;
            s.code[q] = (s.code[q] & ~weight) | ((verdict[q] & kSettledOne) != 0 ? weight : 0u);
        }
    }
}

// The one bit per pixel left for the phase or the bins' edge to settle: a pixel's only open bit
// where flipping it names the next bin (an edge, kept open even where the neighbours lean one
// way), else the one bit its neighbours could not settle; more than one left is ambiguous.
void PhaseShiftDecoder::markUncertainBits(int a) {
    AxisState& s = state_[a];
    s.uncertain.assign(pixels_, kNoUncertainBit);
    const auto lowestBit = [](std::uint32_t mask) {
        return static_cast<std::int8_t>(__builtin_ctz(mask));
    };
    for (const std::size_t q : lit_) {
        const std::uint32_t open = s.open[q];
        if (open == 0) {
            continue;
        }
        if ((open & (open - 1)) == 0) {
            const auto here = static_cast<long>(proto::grayDecode(s.code[q]));
            const auto flipped = static_cast<long>(proto::grayDecode(s.code[q] ^ open));
            if ((s.settled[q] & open) == 0 || std::abs(here - flipped) == 1) {
                s.uncertain[q] = lowestBit(open);
                continue;
            }
        }
        const std::uint32_t left = open & ~s.settled[q];
        if (left == 0) {
            continue;
        }
        s.uncertain[q] = (left & (left - 1)) == 0 ? lowestBit(left) : kTooManyUncertainBits;
    }
}

// Σ I_s sin δ_s and Σ I_s cos δ_s of axis `a` over its phase shifts, at the lit pixels.
void PhaseShiftDecoder::accumulatePhase(int a) {
    const proto::PatternAxis axis = kAxes[a];
    AxisState& s = state_[a];
    s.sine.assign(pixels_, 0.0f);
    s.cosine.assign(pixels_, 0.0f);
    for (int step = 0; step < parameters_.phaseSteps; ++step) {
        const proto::PatternSpec pattern{proto::PatternKind::kPhase, axis, 0, false, step};
        const std::vector<float> image = load(pattern);
        std::vector<double> share;
        for (std::size_t k = 0; k < lit_.size(); k += 7) {
            const std::size_t q = lit_[k];
            share.push_back((double(image[q]) - double(scan_.black[q])) /
                            (double(scan_.white[q]) - double(scan_.black[q])));
        }
        const double m = common::quantile(share, 0.5);
        if (!(m > 0.02 && m < 0.98)) {
            throw common::InputError(pathOf(pattern),
                                     std::string(m <= 0.02 ? "black" : "saturated") +
                                         ": its lit pixels hold " +
                                         std::to_string(static_cast<int>(std::lround(100 * m))) +
                                         "% of white − black (pattern '" + pattern.name() + "')");
        }
        const double delta = 2 * kPi * step / parameters_.phaseSteps;
        const auto c = static_cast<float>(std::cos(delta)),
                   sn = static_cast<float>(std::sin(delta));
        for (const std::size_t q : lit_) {
            s.sine[q] += image[q] * sn;
            s.cosine[q] += image[q] * c;
        }
    }
}

// Axis `a` of pixel q by its Gray code alone: the bin's centre, or with one bit open the edge
// between the two bins it names; σ = the bin's width / √12.
AxisPosition PhaseShiftDecoder::placeByGrayBin(int a, std::size_t q) const {
    const AxisState& s = state_[a];
    const double binWidth = sequence_.grayBinWidth();
    const int extent = a == 0 ? parameters_.width : parameters_.height;
    AxisPosition placed;
    placed.source = PositionSource::kGrayBin;
    placed.sigma = binWidth / std::sqrt(12.0);
    const auto bin = static_cast<double>(proto::grayDecode(s.code[q]));
    if (s.uncertain[q] == kNoUncertainBit) {
        const double start = bin * binWidth;
        placed.position = (start + std::min(start + binWidth, double(extent)) - 1) / 2;
        if (start >= extent) {
            placed.status = DecodeStatus::kInconsistent;  // a code the projector does not have
        }
        return placed;
    }
    const auto other = static_cast<double>(
        proto::grayDecode(s.code[q] ^ (1u << static_cast<unsigned>(s.uncertain[q]))));
    const double edge = std::max(bin, other) * binWidth;
    placed.position = edge - 0.5;
    if (std::abs(bin - other) != 1) {
        placed.status = DecodeStatus::kAmbiguous;
    } else if (edge >= extent) {
        placed.status = DecodeStatus::kInconsistent;
    }
    return placed;
}

// Axis `a` of lit pixel q: the phase inside the Gray code's bin, summed over the pixel's 3 × 3
// or 5 × 5 neighbourhood when the camera's noise leaves the pixel's own σ above maxSigma (the
// neighbours' phasors add: a smooth surface's mean is the centre's coordinate), and the Gray bin
// when even that does not reach maxSigma or the phase is too weak. A phase precise enough that
// disagrees with the code is a pixel the decoder cannot trust (kInconsistent).
AxisPosition PhaseShiftDecoder::placeAxis(int a, std::size_t q,
                                          const std::vector<std::uint8_t>& isLit) const {
    const AxisState& s = state_[a];
    if (s.uncertain[q] == kTooManyUncertainBits) {
        return {DecodeStatus::kAmbiguous, PositionSource::kNone, 0, 0};
    }
    const double period = parameters_.phasePeriod, steps = parameters_.phaseSteps;
    const double binWidth = sequence_.grayBinWidth();
    const int extent = a == 0 ? parameters_.width : parameters_.height;
    const int w = scan_.width, h = scan_.height;
    const int x = static_cast<int>(q % static_cast<std::size_t>(w));
    const int y = static_cast<int>(q / static_cast<std::size_t>(w));
    const auto centreBin = static_cast<long>(proto::grayDecode(s.code[q]));
    // σ(θ) = σ_I·√(2/N)/A for N steps of amplitude A; the noise at the mean level; n pixels'
    // phasors divide it by √n.
    const double sigmaI =
        scan_.noise.sigma(0.5 * (double(scan_.white[q]) + double(scan_.black[q])));
    // Neighbours help where the camera's noise, not the geometry, makes the pixel imprecise: a
    // pixel as bright as the object's typical one. A dim one (grazing, at a silhouette or a
    // shadow's edge) is where neighbours lie on a surface bending away: the Gray bin places it.
    const int largestRadius =
        double(scan_.direct[q]) >= kNoisyButBright * typicalDirect_ ? kLargestRadius : 0;
    // A neighbour counts when lit and on the same surface (its bin the centre's or next to it).
    const auto usable = [&](int u, int v) {
        if (u < 0 || v < 0 || u >= w || v >= h) {
            return false;
        }
        const std::size_t r = static_cast<std::size_t>(v) * w + u;
        return isLit[r] != 0 &&
               std::abs(static_cast<long>(proto::grayDecode(s.code[r])) - centreBin) <= 1;
    };
    for (int radius = 0; radius <= largestRadius; ++radius) {
        // Neighbours in mirrored pairs only: the offsets' mean stays the centre, so a surface's
        // gradient adds no bias, and a silhouette or a step only narrows the neighbourhood.
        double sine = double(s.sine[q]), cosine = double(s.cosine[q]), n = 1;
        for (int dy = 0; dy <= radius; ++dy) {
            for (int dx = -radius; dx <= radius; ++dx) {
                if (dy == 0 && dx <= 0) {
                    continue;  // the other half of the pairs, and the centre
                }
                if (!usable(x + dx, y + dy) || !usable(x - dx, y - dy)) {
                    continue;
                }
                for (const int side : {1, -1}) {
                    const std::size_t r =
                        static_cast<std::size_t>(y + side * dy) * w + (x + side * dx);
                    sine += double(s.sine[r]);
                    cosine += double(s.cosine[r]);
                }
                n += 2;
            }
        }
        if (radius > 0 && n <= 1) {
            break;  // no neighbour to help
        }
        const double amplitude = 2.0 / steps * std::hypot(sine, cosine) / n;
        if (amplitude < options_.minModulation * double(scan_.direct[q])) {
            // Weak against the direct light, not the noise: blur or two surfaces mixed in the
            // pixel, where the Gray code is no better.
            return {DecodeStatus::kLowModulation, PositionSource::kNone, 0, 0};
        }
        const double sigma =
            period / (2 * kPi) * sigmaI * std::sqrt(2.0 / steps) / amplitude / std::sqrt(n);
        if (sigma > options_.maxSigma) {
            continue;
        }
        double angle = std::atan2(sine, cosine);
        if (angle < 0) {
            angle += 2 * kPi;
        }
        angle = correctedPhase(a, angle);
        const double inPeriod = angle / (2 * kPi) * period;
        // The candidates: the code as read, and with the undecided bit flipped when the two codes
        // are neighbours (an edge between two bins); the phase picks.
        std::uint32_t candidates[2] = {s.code[q], s.code[q]};
        int count = 1;
        if (s.uncertain[q] >= 0) {
            candidates[1] ^= 1u << s.uncertain[q];
            const auto b0 = static_cast<long>(proto::grayDecode(candidates[0]));
            const auto b1 = static_cast<long>(proto::grayDecode(candidates[1]));
            if (std::abs(b0 - b1) != 1) {
                return {DecodeStatus::kAmbiguous, PositionSource::kNone, 0, 0};
            }
            count = 2;
        }
        double best = std::numeric_limits<double>::infinity(), chosen = 0;
        for (int c = 0; c < count; ++c) {
            const double bin = proto::grayDecode(candidates[c]);
            const double coarse = bin * binWidth + (binWidth - 1) / 2;
            const double turns = std::round((coarse - inPeriod) / period);
            const double candidate = inPeriod + turns * period;
            if (std::abs(candidate - coarse) < best) {
                best = std::abs(candidate - coarse);
                chosen = candidate;
            }
        }
        // Inside its bin the phase sits within half a bin of the bin's centre; an edge read on
        // the wrong side adds one bin.
        if (best > 1.5 * binWidth || chosen < -0.5 || chosen > extent - 0.5) {
            return {DecodeStatus::kInconsistent, PositionSource::kNone, 0, 0};
        }
        return {DecodeStatus::kDecoded,
                radius == 0 ? PositionSource::kPhase : PositionSource::kPhaseNeighbourhood, chosen,
                sigma};
    }
    return placeByGrayBin(a, q);
}

// A distortion every pixel's phase images share — a DLP projector's bit-planes caught by an
// exposure shorter than its frames, a lamp flickering — bends the decoded phase by one
// function of the true phase (the blur and the pixel's own level cancel in the angle). Over an
// object many periods wide the true phase is spread evenly, so where the decoded phase's
// histogram is not, its cumulative distribution maps it back (histogram equalization), and the
// Gray codes set the one constant that leaves open. DecodedScan::phaseDistortion reports the
// departure; phaseEqualized whether it was undone.
void PhaseShiftDecoder::equalizePhase(int a) {
    const AxisState& s = state_[a];
    std::vector<double> count(kPhaseBins, 0.0);
    std::vector<std::size_t> bright;
    for (const std::size_t q : lit_) {
        if (double(scan_.direct[q]) >= typicalDirect_) {
            bright.push_back(q);
        }
    }
    const auto wrappedAngle = [&](std::size_t q) {
        const double angle = std::atan2(double(s.sine[q]), double(s.cosine[q]));
        return angle < 0 ? angle + 2 * kPi : angle;
    };
    for (const std::size_t q : bright) {
        const int bin = static_cast<int>(wrappedAngle(q) / (2 * kPi) * kPhaseBins);
        count[static_cast<std::size_t>(std::clamp(bin, 0, kPhaseBins - 1))] += 1;
    }
    const double mean = double(bright.size()) / kPhaseBins;
    double worst = 0;
    for (const double c : count) {
        worst = std::max(worst, std::abs(c / mean - 1));
    }
    scan_.phaseDistortion[a] = worst;
    const double threshold = std::max(kDistortedPhase, 4.5 / std::sqrt(std::max(mean, 1.0)));
    if (bright.size() < 100 * kPhaseBins || worst <= threshold) {
        return;
    }
    std::vector<double>& cdf = phaseCdf_[a];
    cdf.assign(kPhaseBins + 1, 0.0);
    for (int k = 0; k < kPhaseBins; ++k) {
        cdf[static_cast<std::size_t>(k) + 1] =
            cdf[static_cast<std::size_t>(k)] + count[static_cast<std::size_t>(k)];
    }
    for (double& value : cdf) {
        value /= cdf.back();
    }
    // The constant: the equalized phase against the Gray bins' centres, on pixels whose every
    // bit is certain (the circular mean of the difference; the in-bin spread is symmetric).
    const double period = parameters_.phasePeriod, binWidth = sequence_.grayBinWidth();
    double sx = 0, sy = 0;
    for (const std::size_t q : bright) {
        if (s.uncertain[q] != kNoUncertainBit) {
            continue;
        }
        const double coarse = double(proto::grayDecode(s.code[q])) * binWidth + (binWidth - 1) / 2;
        const double difference =
            correctedPhase(a, wrappedAngle(q)) - 2 * kPi * std::fmod(coarse, period) / period;
        sx += std::cos(difference);
        sy += std::sin(difference);
    }
    phaseOffset_[a] = std::atan2(sy, sx);
    // An uneven histogram may also be the object's own (a few periods, a steep wing, a
    // concave corner's bounce bending the phase near its crease): keep the equalization only
    // where it brings the pixels on a Gray edge (the lowest bit left open) closer to that edge.
    const auto edgeRms = [&](bool equalized) {
        double squares = 0, n = 0;
        for (const std::size_t q : bright) {
            if (s.uncertain[q] != 0) {
                continue;
            }
            const double b0 = proto::grayDecode(s.code[q]), b1 = proto::grayDecode(s.code[q] ^ 1u);
            const double edge = std::max(b0, b1) * binWidth - 0.5;
            const double angle = equalized ? correctedPhase(a, wrappedAngle(q)) : wrappedAngle(q);
            double offset = std::fmod(angle / (2 * kPi) * period - edge, period);
            offset -= period * std::round(offset / period);
            squares += offset * offset;
            n += 1;
        }
        return n > 0 ? std::sqrt(squares / n) : 0.0;
    };
    const double before = edgeRms(false), after = edgeRms(true);
    scan_.phaseEqualized[a] = after < kEqualizationGain * before;
    if (!scan_.phaseEqualized[a]) {
        cdf.clear();
        phaseOffset_[a] = 0;
    }
}

double PhaseShiftDecoder::correctedPhase(int a, double angle) const {
    const std::vector<double>& cdf = phaseCdf_[a];
    if (cdf.empty()) {
        return angle;
    }
    const double at = angle / (2 * kPi) * kPhaseBins;
    const int bin = std::clamp(static_cast<int>(at), 0, kPhaseBins - 1);
    const double share =
        cdf[static_cast<std::size_t>(bin)] +
        (at - bin) * (cdf[static_cast<std::size_t>(bin) + 1] - cdf[static_cast<std::size_t>(bin)]);
    const double corrected = 2 * kPi * share - phaseOffset_[a];
    return corrected - 2 * kPi * std::floor(corrected / (2 * kPi));
}

void PhaseShiftDecoder::placePixels() {
    scan_.projectorX.assign(pixels_, kNaN);
    scan_.projectorY.assign(pixels_, kNaN);
    scan_.precision.assign(pixels_, kNaN);
    scan_.source.assign(pixels_, PositionSource::kNone);
    std::vector<std::uint8_t> isLit(pixels_, 0);
    for (const std::size_t q : lit_) {
        isLit[q] = 1;
    }
    common::parallelFor(lit_.size(), kGrain, threads_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t q = lit_[k];
            AxisPosition axes[2];
            DecodeStatus status = DecodeStatus::kDecoded;
            for (int a = 0; a < 2 && status == DecodeStatus::kDecoded; ++a) {
                axes[a] = placeAxis(a, q, isLit);
                status = axes[a].status;
            }
            scan_.status[q] = status;
            if (status == DecodeStatus::kDecoded) {
                scan_.projectorX[q] = static_cast<float>(axes[0].position);
                scan_.projectorY[q] = static_cast<float>(axes[1].position);
                scan_.precision[q] = static_cast<float>(std::max(axes[0].sigma, axes[1].sigma));
                scan_.source[q] = std::max(axes[0].source, axes[1].source);
            }
        }
    });
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

const char* positionSourceName(PositionSource source) {
    switch (source) {
        case PositionSource::kNone:
            return "none";
        case PositionSource::kPhase:
            return "phase";
        case PositionSource::kPhaseNeighbourhood:
            return "phase_neighbourhood";
        case PositionSource::kGrayBin:
            return "gray_bin";
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
    return PhaseShiftDecoder(capture, options).decode();
}

}  // namespace vpe::structured_light
