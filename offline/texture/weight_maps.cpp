// SPDX-License-Identifier: MIT
// Weight spec parsing, the procedural generators, image weights and normalization.
#include "vpe/texture/weight_maps.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "vpe/common/input_error.h"
#include "vpe/common/procedural_noise.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/luminance.h"
#include "vpe/segment/label_map.h"

namespace vpe::texture {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Prefix of every message about one entry: `--weights entry 2 'stripes:angle=x'`.
std::string entryLabel(std::string_view origin, int index, std::string_view entry) {
    return std::string(origin) + " entry " + std::to_string(index) + " '" + std::string(entry) +
           "'";
}

std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> parts;
    std::size_t begin = 0;
    while (true) {
        const std::size_t end = text.find(separator, begin);
        parts.push_back(text.substr(begin, end == std::string_view::npos ? end : end - begin));
        if (end == std::string_view::npos) {
            return parts;
        }
        begin = end + 1;
    }
}

// Parses one entry's parameters against the names its kind accepts.
class ParameterParser {
public:
    ParameterParser(std::string label, std::vector<std::string_view> accepted)
        : label_(std::move(label)), accepted_(std::move(accepted)) {}

    // Returns the parameter's name; "invert" is a flag, set here, and returns "".
    std::string_view parse(std::string_view parameter, WeightSource& source) {
        if (parameter == "invert") {
            if (std::find(accepted_.begin(), accepted_.end(), "invert") == accepted_.end()) {
                fail("'invert' does not apply here" + acceptedList());
            }
            remember("invert");
            source.invert = true;
            return {};
        }
        const std::size_t equals = parameter.find('=');
        if (equals == std::string_view::npos || equals == 0) {
            fail("'" + std::string(parameter) + "' is not NAME=VALUE" + acceptedList());
        }
        name_ = parameter.substr(0, equals);
        value_ = parameter.substr(equals + 1);
        if (std::find(accepted_.begin(), accepted_.end(), name_) == accepted_.end() ||
            name_ == "invert") {
            fail("unknown parameter '" + std::string(name_) + "'" + acceptedList());
        }
        remember(name_);
        return name_;
    }

    double number(double low, double high, bool lowInclusive = true) const {
        double value = 0;
        const char* end = value_.data() + value_.size();
        const auto [ptr, error] = std::from_chars(value_.data(), end, value);
        if (value_.empty() || error != std::errc() || ptr != end || !std::isfinite(value)) {
            fail(std::string(name_) + ": '" + std::string(value_) + "' is not a number");
        }
        if (value > high || value < low || (!lowInclusive && value == low)) {
            fail(std::string(name_) + " = " + std::string(value_) + " is out of range " +
                 (lowInclusive ? "[" : "(") + format(low) + ", " + format(high) + "]");
        }
        return value;
    }
    std::uint64_t integer(std::uint64_t low, std::uint64_t high) const {
        std::uint64_t value = 0;
        const char* end = value_.data() + value_.size();
        const auto [ptr, error] = std::from_chars(value_.data(), end, value);
        if (value_.empty() || error != std::errc() || ptr != end) {
            fail(std::string(name_) + ": '" + std::string(value_) +
                 "' is not a non-negative integer");
        }
        if (value < low || value > high) {
            fail(std::string(name_) + " = " + std::string(value_) + " is out of range [" +
                 std::to_string(low) + ", " + std::to_string(high) + "]");
        }
        return value;
    }
    std::string_view text() const { return value_; }
    [[noreturn]] void fail(const std::string& problem) const {
        throw common::InputError(label_ + ": " + problem);
    }

private:
    void remember(std::string_view name) {
        if (!seen_.insert(std::string(name)).second) {
            fail("'" + std::string(name) + "' given twice");
        }
    }
    std::string acceptedList() const {
        if (accepted_.empty()) {
            return " (this kind takes no parameters)";
        }
        std::string list = " (accepted:";
        for (std::string_view name : accepted_) {
            list += " " + std::string(name);
        }
        return list + ")";
    }
    static std::string format(double value) {
        if (std::isinf(value)) {
            return value > 0 ? "inf" : "-inf";
        }
        char text[32];
        std::snprintf(text, sizeof text, "%g", value);
        return text;
    }

    std::string label_;
    std::vector<std::string_view> accepted_;
    std::set<std::string> seen_;
    std::string_view name_;
    std::string_view value_;
};

void parseStrokes(ParameterParser parser, const std::vector<std::string_view>& parts,
                  WeightSource& source) {
    constexpr double kMaxLength = 1e5;  // texels: far beyond any texture, catches typos
    StrokeParameters& strokes = source.strokes;
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const std::string_view name = parser.parse(parts[i], source);
        if (name == "from") {
            if (parser.text().empty()) {
                parser.fail("from needs a label image, as in from=labels.png");
            }
            strokes.labels = std::filesystem::path(std::string(parser.text()));
        } else if (name == "region") {
            strokes.region = static_cast<int>(parser.integer(0, segment::LabelMap::kMaxLabels - 1));
        } else if (name == "coverage") {
            strokes.coverage = parser.number(0, 0.9, false);
        } else if (name == "count") {
            strokes.count = static_cast<int>(parser.integer(1, 100000));
        } else if (name == "width") {
            strokes.width = parser.number(0.5, kMaxLength);
        } else if (name == "spread") {
            strokes.spread = parser.number(0, 2);
        } else if (name == "wobble") {
            strokes.wobble = parser.number(0, 1);
        } else if (name == "length") {
            strokes.length = parser.number(1, kMaxLength);
        } else if (name == "bend") {
            strokes.bend = parser.number(0, 360);
        } else if (name == "softness") {
            strokes.softness = parser.number(0, kMaxLength);
        } else if (name == "angle") {
            strokes.angleDegrees = parser.number(-360, 360);
        } else if (name == "angle-spread") {
            strokes.angleSpread = parser.number(0, 360);
        } else if (name == "seed") {
            strokes.seed = parser.integer(0, UINT64_MAX);
        } else if (name == "wrap") {
            const std::string_view wrap = parser.text();
            if (wrap == "none") {
                strokes.wrap = StrokeWrap::kNone;
            } else if (wrap == "u") {
                strokes.wrap = StrokeWrap::kU;
            } else if (wrap == "uv") {
                strokes.wrap = StrokeWrap::kUV;
            } else {
                parser.fail("wrap: '" + std::string(wrap) + "' is not none, u or uv");
            }
        }
    }
    if (strokes.coverage && strokes.count) {
        parser.fail("coverage and count both given (one decides how many strokes)");
    }
    if (strokes.region && strokes.labels.empty()) {
        parser.fail("region needs from=LABELS (the label image it is a region of)");
    }
    if (!strokes.labels.empty() && !strokes.region) {
        parser.fail("from needs region=R (the label whose streaks to measure)");
    }
}

void parseQuilted(ParameterParser parser, const std::vector<std::string_view>& parts,
                  WeightSource& source) {
    LabelQuiltParameters& quilted = source.labelQuilt;
    bool hasRegion = false;
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const std::string_view name = parser.parse(parts[i], source);
        if (name == "from") {
            if (parser.text().empty()) {
                parser.fail("from needs a label image, as in from=labels.png");
            }
            quilted.labels = std::filesystem::path(std::string(parser.text()));
        } else if (name == "region") {
            quilted.region = static_cast<int>(parser.integer(0, segment::LabelMap::kMaxLabels - 1));
            hasRegion = true;
        } else if (name == "block") {
            quilted.block = static_cast<int>(parser.integer(8, 4096));
        } else if (name == "overlap") {
            quilted.overlap = static_cast<int>(parser.integer(1, 2048));
        } else if (name == "softness") {
            quilted.softness = parser.number(0, 1e5);
        } else if (name == "seed") {
            quilted.seed = parser.integer(0, UINT64_MAX);
        }
    }
    if (quilted.labels.empty() || !hasRegion) {
        parser.fail("quilted needs from=LABELS and region=R (the label map and its label)");
    }
}

WeightSource parseEntry(std::string_view origin, int index, std::string_view entry) {
    const std::string label = entryLabel(origin, index, entry);
    WeightSource source;
    source.entry = std::string(entry);
    source.index = index;
    if (entry.empty()) {
        throw common::InputError(label +
                                 ": empty entry (one entry per region, separated by commas)");
    }
    std::vector<std::string_view> parts = split(entry, ':');
    const std::string_view kind = parts.front();
    std::size_t first = 1;
    constexpr double kInf = INFINITY;
    if (kind == "image") {
        source.kind = WeightKind::kImage;
        if (parts.size() < 2 || parts[1].empty()) {
            throw common::InputError(label + ": image needs a path, as in image:weights.png");
        }
        source.image = std::filesystem::path(std::string(parts[1]));
        first = 2;
        ParameterParser parser(label, {"invert"});
        for (std::size_t i = first; i < parts.size(); ++i) {
            parser.parse(parts[i], source);
        }
        return source;
    }
    const double maxLength = 1e6;  // pixels: far beyond any texture, catches typos
    if (kind == "stripes") {
        source.kind = WeightKind::kStripes;
        ParameterParser parser(label, {"angle", "period", "sharpness", "phase", "invert"});
        for (std::size_t i = first; i < parts.size(); ++i) {
            const std::string_view name = parser.parse(parts[i], source);
            if (name == "angle") {
                source.angleDegrees = parser.number(-360, 360);
            } else if (name == "period") {
                source.period = parser.number(0, maxLength, false);
            } else if (name == "sharpness") {
                source.sharpness = parser.number(0, 100);
            } else if (name == "phase") {
                source.phase = parser.number(-kInf, kInf);
            }
        }
    } else if (kind == "radial") {
        source.kind = WeightKind::kRadial;
        ParameterParser parser(label, {"cx", "cy", "radius", "invert"});
        for (std::size_t i = first; i < parts.size(); ++i) {
            const std::string_view name = parser.parse(parts[i], source);
            if (name == "cx") {
                source.centreX = parser.number(-maxLength, maxLength);
            } else if (name == "cy") {
                source.centreY = parser.number(-maxLength, maxLength);
            } else if (name == "radius") {
                source.radius = parser.number(0, maxLength, false);
            }
        }
    } else if (kind == "noise") {
        source.kind = WeightKind::kNoise;
        ParameterParser parser(label, {"scale", "seed", "octaves", "sharpness", "invert"});
        for (std::size_t i = first; i < parts.size(); ++i) {
            const std::string_view name = parser.parse(parts[i], source);
            if (name == "scale") {
                source.scale = parser.number(0, maxLength, false);
            } else if (name == "seed") {
                source.seed = parser.integer(0, UINT64_MAX);
            } else if (name == "octaves") {
                source.octaves = static_cast<int>(parser.integer(1, 8));
            } else if (name == "sharpness") {
                source.sharpness = parser.number(0, 100);
            }
        }
    } else if (kind == "strokes") {
        source.kind = WeightKind::kStrokes;
        parseStrokes(ParameterParser(label, {"from", "region", "coverage", "count", "width",
                                             "spread", "wobble", "length", "bend", "softness",
                                             "angle", "angle-spread", "seed", "wrap", "invert"}),
                     parts, source);
    } else if (kind == "quilted") {
        source.kind = WeightKind::kQuilted;
        parseQuilted(ParameterParser(label, {"from", "region", "block", "overlap", "softness",
                                             "seed", "invert"}),
                     parts, source);
    } else if (kind == "constant") {
        source.kind = WeightKind::kConstant;
        ParameterParser parser(label, {"value"});
        for (std::size_t i = first; i < parts.size(); ++i) {
            parser.parse(parts[i], source);
            source.value = parser.number(0, 1e6);
        }
    } else {
        throw common::InputError(label + ": unknown kind '" + std::string(kind) +
                                 "' (image, stripes, radial, noise, strokes, quilted, constant)");
    }
    return source;
}

// Maps s ∈ [-1, 1] to [0, 1]; sharpness k > 0 pushes values towards 0 and 1 (tanh k s),
// keeping ±1 fixed so the contrast range does not depend on k.
double profile(double s, double sharpness) {
    const double shaped = sharpness > 0 ? std::tanh(sharpness * s) / std::tanh(sharpness) : s;
    return std::clamp(0.5 + 0.5 * shaped, 0.0, 1.0);
}

// Grey value of an image pixel: the single channel, grey of grey + alpha, or the Rec. 709
// luma of RGB(A) as stored.
float greyAt(const image::FloatImage& image, int x, int y) {
    if (image.channels < 3) {
        return image.at(x, y, 0);
    }
    return proto::luminance709f(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
}

std::vector<float> imageWeight(const WeightSource& source, int width, int height) {
    const image::FloatImage image = image::readImage(source.image);
    std::vector<float> grey(static_cast<std::size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float value = greyAt(image, x, y);
            if (!std::isfinite(value) || value < 0) {
                throw common::InputError(source.image, "pixel (" + std::to_string(x) + ", " +
                                                           std::to_string(y) +
                                                           "): a weight must be finite and ≥ 0");
            }
            grey[static_cast<std::size_t>(y) * image.width + x] = value;
        }
    }
    if (image.width == width && image.height == height) {
        return grey;
    }
    // Bilinear with pixel centres aligned (the image's corners land on the output's corners),
    // clamped at the borders.
    std::vector<float> out(static_cast<std::size_t>(width) * height);
    const double sx = static_cast<double>(image.width) / width;
    const double sy = static_cast<double>(image.height) / height;
    for (int y = 0; y < height; ++y) {
        const double fy = std::clamp((y + 0.5) * sy - 0.5, 0.0, image.height - 1.0);
        const int y0 = static_cast<int>(fy);
        const int y1 = std::min(y0 + 1, image.height - 1);
        const double ty = fy - y0;
        for (int x = 0; x < width; ++x) {
            const double fx = std::clamp((x + 0.5) * sx - 0.5, 0.0, image.width - 1.0);
            const int x0 = static_cast<int>(fx);
            const int x1 = std::min(x0 + 1, image.width - 1);
            const double tx = fx - x0;
            auto g = [&](int gx, int gy) {
                return static_cast<double>(grey[static_cast<std::size_t>(gy) * image.width + gx]);
            };
            const double top = g(x0, y0) + tx * (g(x1, y0) - g(x0, y0));
            const double bottom = g(x0, y1) + tx * (g(x1, y1) - g(x0, y1));
            out[static_cast<std::size_t>(y) * width + x] =
                static_cast<float>(top + ty * (bottom - top));
        }
    }
    return out;
}

}  // namespace

std::vector<WeightSource> parseWeightSpec(std::string_view spec, std::string_view origin) {
    if (spec.empty()) {
        throw common::InputError(std::string(origin) +
                                 ": empty weight spec (one entry per region)");
    }
    std::vector<WeightSource> sources;
    int index = 1;
    for (std::string_view entry : split(spec, ',')) {
        sources.push_back(parseEntry(origin, index++, entry));
    }
    return sources;
}

std::vector<float> generateWeight(const WeightSource& source, int width, int height) {
    std::vector<float> out(static_cast<std::size_t>(width) * height);
    if (source.kind == WeightKind::kImage) {
        out = imageWeight(source, width, height);
        if (source.invert) {
            for (float& v : out) {
                v = std::max(1.0f - v, 0.0f);
            }
        }
        return out;
    }
    if (source.kind == WeightKind::kStrokes || source.kind == WeightKind::kQuilted) {
        out = source.kind == WeightKind::kStrokes
                  ? generateStrokes(resolveStrokes(source.strokes), width, height).weight
                  : quiltLabelPattern(source.labelQuilt, width, height);
        if (source.invert) {
            for (float& v : out) {
                v = 1.0f - v;
            }
        }
        return out;
    }
    const double angle = source.angleDegrees * kPi / 180.0;
    // Image y points down, so counter-clockwise as seen is (cos a, −sin a); the wave runs
    // along the perpendicular (sin a, cos a).
    const double acrossX = std::sin(angle), acrossY = std::cos(angle);
    const double cx = source.centreX.value_or(0.5 * width);
    const double cy = source.centreY.value_or(0.5 * height);
    const double radius = source.radius.value_or(0.5 * std::min(width, height));
    const common::GradientNoise noise(source.seed);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            // Pixel centres, so a map and its transpose or mirror agree.
            const double px = x + 0.5, py = y + 0.5;
            double value = 0;
            switch (source.kind) {
                case WeightKind::kStripes: {
                    const double across = px * acrossX + py * acrossY;
                    value = profile(std::sin(2 * kPi * (across / source.period + source.phase)),
                                    source.sharpness);
                    break;
                }
                case WeightKind::kRadial:
                    value = std::max(1.0 - std::hypot(px - cx, py - cy) / radius, 0.0);
                    break;
                case WeightKind::kNoise:
                    value =
                        profile(noise.fractal(px / source.scale, py / source.scale, source.octaves),
                                source.sharpness);
                    break;
                case WeightKind::kConstant:
                case WeightKind::kImage:
                case WeightKind::kStrokes:
                case WeightKind::kQuilted:
                    value = source.value;
                    break;
            }
            if (source.invert) {
                value = 1.0 - value;
            }
            out[static_cast<std::size_t>(y) * width + x] = static_cast<float>(value);
        }
    }
    return out;
}

void normalizeWeightMaps(WeightMaps& maps) {
    const std::size_t pixels = static_cast<std::size_t>(maps.width) * maps.height;
    const int regions = maps.regions();
    maps.zeroSumPixels = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        double sum = 0;
        for (int k = 0; k < regions; ++k) {
            sum += static_cast<double>(maps.alpha[static_cast<std::size_t>(k)][p]);
        }
        if (sum > 0) {
            for (int k = 0; k < regions; ++k) {
                float& a = maps.alpha[static_cast<std::size_t>(k)][p];
                a = static_cast<float>(static_cast<double>(a) / sum);
            }
        } else {
            ++maps.zeroSumPixels;
            for (int k = 0; k < regions; ++k) {
                maps.alpha[static_cast<std::size_t>(k)][p] = 1.0f / static_cast<float>(regions);
            }
        }
    }
}

WeightMaps buildWeightMaps(const std::vector<WeightSource>& sources, int width, int height) {
    WeightMaps maps;
    maps.width = width;
    maps.height = height;
    for (const WeightSource& source : sources) {
        maps.alpha.push_back(generateWeight(source, width, height));
    }
    normalizeWeightMaps(maps);
    return maps;
}

void writeWeightPicture(const std::filesystem::path& path, const WeightMaps& maps) {
    // Distinct colours (Tableau 10), sRGB.
    static constexpr std::uint8_t kPalette[10][3] = {
        {78, 121, 167}, {242, 142, 43},  {225, 87, 89},   {118, 183, 178}, {89, 161, 79},
        {237, 201, 72}, {176, 122, 161}, {255, 157, 167}, {156, 117, 95},  {186, 176, 172}};
    constexpr int kMaxTile = 512;
    constexpr int kGap = 4;
    const int factor = std::max(1, (std::max(maps.width, maps.height) + kMaxTile - 1) / kMaxTile);
    const int tileW = std::max(1, maps.width / factor);
    const int tileH = std::max(1, maps.height / factor);
    const int regions = maps.regions();
    const int tiles = regions + 1;
    const int width = tiles * tileW + (tiles - 1) * kGap;
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * tileH * 3, 40);
    auto put = [&](int x, int y, double r, double g, double b) {
        std::uint8_t* out = pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3;
        out[0] = static_cast<std::uint8_t>(std::lround(std::clamp(r, 0.0, 255.0)));
        out[1] = static_cast<std::uint8_t>(std::lround(std::clamp(g, 0.0, 255.0)));
        out[2] = static_cast<std::uint8_t>(std::lround(std::clamp(b, 0.0, 255.0)));
    };
    std::vector<double> mean(static_cast<std::size_t>(regions));
    for (int ty = 0; ty < tileH; ++ty) {
        for (int tx = 0; tx < tileW; ++tx) {
            // Box filter over the factor × factor block: a downscaled map keeps its mean.
            std::fill(mean.begin(), mean.end(), 0.0);
            for (int dy = 0; dy < factor; ++dy) {
                for (int dx = 0; dx < factor; ++dx) {
                    const int x = std::min(tx * factor + dx, maps.width - 1);
                    const int y = std::min(ty * factor + dy, maps.height - 1);
                    for (int k = 0; k < regions; ++k) {
                        mean[static_cast<std::size_t>(k)] += static_cast<double>(maps.at(k, x, y));
                    }
                }
            }
            double r = 0, g = 0, b = 0;
            for (int k = 0; k < regions; ++k) {
                const double a = mean[static_cast<std::size_t>(k)] / (factor * factor);
                const double grey = 255.0 * a;
                put(k * (tileW + kGap) + tx, ty, grey, grey, grey);
                const std::uint8_t* colour = kPalette[k % 10];
                r += a * colour[0];
                g += a * colour[1];
                b += a * colour[2];
            }
            put(regions * (tileW + kGap) + tx, ty, r, g, b);
        }
    }
    image::writeImage8(path, width, tileH, 3, pixels);
}

}  // namespace vpe::texture
