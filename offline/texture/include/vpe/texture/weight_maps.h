// SPDX-License-Identifier: MIT
// Weight maps (paper eq. 20): one α map per reflectance region at the output size, from grey
// images or procedural generators, normalized so that Σ_k α_k = 1 at every pixel.
//
// The spec (`vpe compose --weights SPEC`) has one entry per region, in region order,
// separated by commas; an entry is a kind and its parameters, separated by colons:
//
//   image:PATH[:invert]                      a grey image (resized bilinearly if needed)
//   stripes[:angle=A][:period=P][:sharpness=S][:phase=F][:invert]
//   radial[:cx=X][:cy=Y][:radius=R][:invert]
//   noise[:scale=L][:seed=N][:octaves=O][:sharpness=S][:invert]
//   strokes[:from=LABELS:region=R][:coverage=C|:count=N][:width=W][:spread=S][:wobble=V]
//          [:length=L][:bend=B][:softness=E][:angle=A][:angle-spread=D][:seed=N]
//          [:wrap=none|u|uv][:invert]            hidasuki bands (texture/stroke_pattern.h)
//   quilted:from=LABELS:region=R[:block=B][:overlap=O][:softness=E][:seed=N][:invert]
//                                            the label map quilted (texture/label_quilt_pattern.h)
//   constant[:value=V]
//
// e.g. "image:streaks.png,stripes:angle=30:period=64:invert,constant:value=0.2". Lengths and
// positions are in output pixels; docs/compose.md gives every default and formula.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/texture/label_quilt_pattern.h"
#include "vpe/texture/stroke_pattern.h"

namespace vpe::texture {

enum class WeightKind { kImage, kStripes, kRadial, kNoise, kStrokes, kQuilted, kConstant };

// One region's raw weight, as parsed from one spec entry.
struct WeightSource {
    WeightKind kind = WeightKind::kConstant;
    std::string entry;  // the entry as written, for messages
    int index = 0;      // 1-based position in the spec, for messages
    bool invert = false;
    // image: grey value as stored (integer formats scaled to [0, 1]; no transfer function,
    // since a weight is not a radiance); RGB images use Rec. 709 luma of the stored values.
    std::filesystem::path image;
    // stripes: a smoothed square wave across the stripes. angle is the direction the stripes
    // run, degrees counter-clockwise from the image's x axis (0: horizontal stripes).
    double angleDegrees = 0;
    double period = 64;
    double phase = 0;      // fraction of a period
    double sharpness = 0;  // 0: sinusoid; larger: closer to a square wave (stripes, noise)
    // radial: 1 at the centre falling linearly to 0 at `radius`. Unset: the output's centre
    // and half its smaller side, resolved at generation time.
    std::optional<double> centreX;
    std::optional<double> centreY;
    std::optional<double> radius;
    // noise: gradient noise of feature size `scale` pixels (common/procedural_noise.h).
    double scale = 32;
    std::uint64_t seed = 1;
    int octaves = 1;
    // strokes
    StrokeParameters strokes;
    // quilted
    LabelQuiltParameters labelQuilt;
    // constant
    double value = 1;
};

// The spec's grammar in one line, for the commands' help.
inline constexpr const char* kWeightSpecSynopsis =
    "One entry per region, comma-separated: image:PATH, "
    "stripes[:angle=A][:period=P][:sharpness=S][:phase=F], radial[:cx=X][:cy=Y][:radius=R], "
    "noise[:scale=L][:seed=N][:octaves=O][:sharpness=S], "
    "strokes[:from=LABELS:region=R][:coverage=C|:count=N][:width=W][:spread=S][:wobble=V]"
    "[:length=L][:bend=B][:softness=E][:angle=A][:angle-spread=D][:seed=N][:wrap=none|u|uv], "
    "quilted:from=LABELS:region=R[:block=B][:overlap=O][:softness=E][:seed=N], "
    "constant[:value=V]; any but constant may add :invert (docs/compose.md)";

// Parses a spec. Throws InputError naming `origin`, the entry (number and text) and the
// problem: unknown kind or parameter, a repeated parameter, a value that is not a number or
// out of range.
std::vector<WeightSource> parseWeightSpec(std::string_view spec,
                                          std::string_view origin = "--weights");

// The raw (unnormalized, ≥ 0) weight of one source at width × height, row-major. Image
// sources are read here; bad pixel values (negative, not finite) throw InputError naming
// the file and the pixel.
std::vector<float> generateWeight(const WeightSource& source, int width, int height);

struct WeightMaps {
    int width = 0;
    int height = 0;
    std::vector<std::vector<float>> alpha;  // [region][y * width + x]
    // Pixels where every raw weight was 0; they get equal weights 1/K (a neutral mix rather
    // than black, which Σ α = 1 forbids anyway).
    std::size_t zeroSumPixels = 0;

    int regions() const { return static_cast<int>(alpha.size()); }
    float at(int region, int x, int y) const {
        return alpha[static_cast<std::size_t>(region)][static_cast<std::size_t>(y) * width + x];
    }
};

// Divides every pixel's weights by their sum (equal weights where the sum is 0).
void normalizeWeightMaps(WeightMaps& maps);

// generateWeight for every source, then normalizeWeightMaps.
WeightMaps buildWeightMaps(const std::vector<WeightSource>& sources, int width, int height);

// A picture for people: one grey tile per region (α from black 0 to white 1), then a tile
// with each region in its own colour mixed by α; tiles at most 512 pixels on a side. Written
// atomically, format from the extension.
void writeWeightPicture(const std::filesystem::path& path, const WeightMaps& maps);

}  // namespace vpe::texture
