// SPDX-License-Identifier: MIT
// The camera response: its table, its fit from a bracket (OpenCV's CalibrateDebevec) and its
// CSV file.
#include "vpe/radiometry/camera_response.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include <opencv2/photo.hpp>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/text/line_reader.h"

namespace vpe::radiometry {

namespace {

constexpr int kEightBitMax = 255;

std::string formatNumber(double value) {
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

// "value" for a monochrome table, else r, g, b: the CSV's column names too.
std::string channelName(int channel, int channels) {
    constexpr const char* kNames[3] = {"r", "g", "b"};
    return channels == 1 ? "value" : kNames[channel];
}

std::string sizeOf(const BracketedImage& image) {
    return std::to_string(image.width) + "x" + std::to_string(image.height);
}

std::string channelsOf(int channels) {
    return std::to_string(channels) + (channels == 1 ? " channel" : " channels");
}

// The value most images share and the images that differ from it; the message names the first
// of those, against "the others" when it is alone, else against an image that has the common
// value.
template <typename Key, typename Describe>
void checkAllAgree(std::span<const BracketedImage> images, Key key, Describe describe,
                   const std::string& verb) {
    std::map<decltype(key(images[0])), int> counts;
    for (const BracketedImage& image : images) {
        ++counts[key(image)];
    }
    if (counts.size() == 1) {
        return;
    }
    // The most common value; ties go to the first image's, the reference a reader expects.
    auto common = key(images[0]);
    for (const auto& [value, count] : counts) {
        if (count > counts[common]) {
            common = value;
        }
    }
    std::size_t odd = 0, reference = 0;
    while (key(images[odd]) == common) {
        ++odd;
    }
    while (key(images[reference]) != common) {
        ++reference;
    }
    const bool alone = counts[common] + 1 == static_cast<int>(images.size());
    throw common::InputError("bracket: image " + std::to_string(odd + 1) + " " + verb + " " +
                             describe(images[odd]) + ", " +
                             (alone ? std::string("the others ")
                                    : "image " + std::to_string(reference + 1) + " " + verb + " ") +
                             describe(images[reference]));
}

void checkBracket(std::span<const BracketedImage> images) {
    const std::size_t count = images.size();
    if (count < 3) {
        throw common::InputError("bracket: " + std::to_string(count) +
                                 (count == 1 ? " image" : " images") +
                                 "; at least 3 exposures are needed");
    }
    for (std::size_t i = 0; i < count; ++i) {
        const BracketedImage& image = images[i];
        const std::string name = "bracket: image " + std::to_string(i + 1);
        if (image.maxValue != kEightBitMax) {
            const int bits = static_cast<int>(std::lround(std::log2(image.maxValue + 1.0)));
            const bool powerOfTwo = image.maxValue > 0 && (1L << bits) == image.maxValue + 1L;
            throw common::InputError(
                name + " is " +
                (powerOfTwo ? std::to_string(bits) + "-bit (maxValue " +
                                  std::to_string(image.maxValue) + ")"
                            : "of maxValue " + std::to_string(image.maxValue)) +
                "; only 8-bit images (maxValue 255) can be bracketed (OpenCV's Debevec)");
        }
        if (image.channels != 1 && image.channels != 3) {
            throw common::InputError(name + " has " + channelsOf(image.channels) +
                                     "; 1 (monochrome) or 3 (RGB) are needed");
        }
        if (image.width <= 0 || image.height <= 0) {
            throw common::InputError(name + " is " + sizeOf(image) + ": empty");
        }
        const std::size_t expected = static_cast<std::size_t>(image.width) *
                                     static_cast<std::size_t>(image.height) *
                                     static_cast<std::size_t>(image.channels);
        if (image.samples.size() != expected) {
            throw common::InputError(name + " holds " + std::to_string(image.samples.size()) +
                                     " samples; " + sizeOf(image) + " with " +
                                     channelsOf(image.channels) + " needs " +
                                     std::to_string(expected));
        }
        if (!std::isfinite(image.exposure) || !(image.exposure > 0)) {
            throw common::InputError(name + ": exposure " + formatNumber(image.exposure) +
                                     " is not a positive number");
        }
        const auto above = std::find_if(image.samples.begin(), image.samples.end(),
                                        [](std::uint16_t v) { return v > kEightBitMax; });
        if (above != image.samples.end()) {
            const std::size_t pixel = static_cast<std::size_t>(above - image.samples.begin()) /
                                      static_cast<std::size_t>(image.channels);
            const std::size_t width = static_cast<std::size_t>(image.width);
            throw common::InputError(name + ", pixel (" + std::to_string(pixel % width) + ", " +
                                     std::to_string(pixel / width) +
                                     "): " + std::to_string(*above) + " is above maxValue 255");
        }
    }
    checkAllAgree(
        images, [](const BracketedImage& image) { return std::pair(image.width, image.height); },
        [](const BracketedImage& image) { return sizeOf(image); }, "is");
    checkAllAgree(
        images, [](const BracketedImage& image) { return image.channels; },
        [](const BracketedImage& image) { return channelsOf(image.channels); }, "has");
    for (std::size_t i = 0; i < count; ++i) {
        for (std::size_t j = 0; j < i; ++j) {
            if (images[i].exposure == images[j].exposure) {
                throw common::InputError("bracket: images " + std::to_string(j + 1) + " and " +
                                         std::to_string(i + 1) + " have the same exposure " +
                                         formatNumber(images[i].exposure) +
                                         "; exposures must differ");
            }
        }
    }
}

// How many pixels the fit samples and how smooth it makes the curve (OpenCV's λ), measured on
// six simulated brackets (tests/offline/radiometry/camera_response_test.cpp's, and other noise
// seeds and ramps): the mean RMS error over codes 16..240 is 2.6 % with 64 pixels and 2.5 % with
// 100, the worst case 47 % and 35 % (the darkest codes); with 100 pixels, 4.1 % at λ = 2 (the noise
// shows), 2.8 % at 5, 2.5 % at 10 (OpenCV's default) and 2.4 % at 20, whose worst case is
// worse (38 %: the smoothing flattens the dark end's curvature). 100 pixels at 5 exposures are
// 500 equations besides the 254 of smoothness, for 256 + 100 unknowns; OpenCV solves them by
// SVD in about 0.2 s per channel on this machine, a time that grows with the cube of the count.
constexpr int kSampleCount = 100;
constexpr float kSmoothness = 10;
// Fewer distinct pixels, or a narrower range of codes in a channel, and the curve would be
// mostly the smoothness term's invention.
constexpr int kMinSamples = 16;
constexpr int kMinCodeSpan = 32;

// Debevec & Malik pick the pixels they fit by hand: a spread of radiances from dark to bright,
// each where the radiance is smooth so that a little blur or misregistration between the frames
// does not matter. OpenCV samples a fixed grid over the frame instead, which on the radiometric
// capture's ramp (constant down each column) sees only as many radiances as the grid has
// columns, and in an installation mostly the dark room around the object. So the pixels are
// chosen here: the range of brightness (the sum of a pixel's codes over the bracket, which
// grows with its radiance whatever the response) is cut into kSampleCount equal steps, and in
// each step the pixel whose neighbourhood is smoothest in the middle exposure (then the one
// nearest the step's centre) is taken. Pixels black or clipped in every image tell nothing
// and are skipped. Returns pixel indices (y·width + x), darkest first.
std::vector<std::size_t> chooseSamplePixels(std::span<const BracketedImage> images) {
    const BracketedImage& first = images.front();
    const int width = first.width, height = first.height, channels = first.channels;
    const std::size_t pixelCount =
        static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const auto sample = [channels](const BracketedImage& image, std::size_t pixel, int c) {
        return static_cast<int>(image.samples[pixel * static_cast<std::size_t>(channels) +
                                              static_cast<std::size_t>(c)]);
    };

    std::vector<int> brightness(pixelCount, 0);
    for (const BracketedImage& image : images) {
        for (std::size_t p = 0; p < pixelCount; ++p) {
            for (int c = 0; c < channels; ++c) {
                brightness[p] += sample(image, p, c);
            }
        }
    }
    const int full = kEightBitMax * channels * static_cast<int>(images.size());
    const auto informative = [full](int b) { return b > 0 && b < full; };
    int lowest = full, highest = 0;
    for (const int b : brightness) {
        if (informative(b)) {
            lowest = std::min(lowest, b);
            highest = std::max(highest, b);
        }
    }

    std::vector<std::size_t> order(images.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return images[a].exposure < images[b].exposure;
    });
    const BracketedImage& middle = images[order[order.size() / 2]];
    // |4·v − the 4 neighbours| summed over the channels; edges repeat their pixels.
    const auto roughness = [&](int x, int y) {
        const auto at = [&](int xx, int yy, int c) {
            xx = std::clamp(xx, 0, width - 1);
            yy = std::clamp(yy, 0, height - 1);
            return sample(middle, static_cast<std::size_t>(yy) * width + xx, c);
        };
        int sum = 0;
        for (int c = 0; c < channels; ++c) {
            sum += std::abs(4 * at(x, y, c) - at(x - 1, y, c) - at(x + 1, y, c) - at(x, y - 1, c) -
                            at(x, y + 1, c));
        }
        return sum;
    };

    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    const long long range = static_cast<long long>(highest) - lowest + 1;
    std::vector<std::size_t> chosen(kSampleCount, kNone);
    std::vector<std::pair<int, long long>> scores(kSampleCount);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * width + x;
            if (!informative(brightness[p])) {
                continue;
            }
            const long long offset = brightness[p] - lowest;
            const auto step = static_cast<std::size_t>(offset * kSampleCount / range);
            // Twice the distance from the step's centre, times kSampleCount: integers.
            const long long fromCentre = std::abs(2 * offset * kSampleCount -
                                                  (2 * static_cast<long long>(step) + 1) * range);
            const std::pair<int, long long> score{roughness(x, y), fromCentre};
            if (chosen[step] == kNone || score < scores[step]) {
                chosen[step] = p;
                scores[step] = score;
            }
        }
    }
    std::erase(chosen, kNone);
    if (static_cast<int>(chosen.size()) < kMinSamples) {
        throw common::InputError(
            "bracket: only " + std::to_string(chosen.size()) +
            (chosen.size() == 1 ? " pixel" : " pixels") + " of distinct brightness (at least " +
            std::to_string(kMinSamples) +
            " are needed); photograph a scene from dark to bright, such as the "
            "radiometric capture's ramp");
    }
    return chosen;
}

// The least-squares line through (ln code, ln value) over codes [from, to], all ≥ 1.
struct PowerLaw {
    double logScale = 0, exponent = 1;

    double at(double code) const { return std::exp(logScale + exponent * std::log(code)); }
};

PowerLaw fitPowerLaw(const std::vector<double>& table, int from, int to) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = to - from + 1;
    for (int code = from; code <= to; ++code) {
        const double x = std::log(static_cast<double>(code));
        const double y = std::log(table[static_cast<std::size_t>(code)]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double spread = n * sxx - sx * sx;
    PowerLaw law;
    // A local gamma outside [0.25, 8] is noise, not a camera (linear is 1, sRGB about 2.3):
    // clamped so that an extrapolation can neither fall towards the top nor explode.
    law.exponent = std::clamp(spread > 0 ? (n * sxy - sx * sy) / spread : 1.0, 0.25, 8.0);
    law.logScale = (sy - law.exponent * sx) / n;
    return law;
}

// Pool adjacent violators: the non-decreasing sequence nearest (least squares) to `values`.
void makeMonotone(std::vector<double>& values) {
    std::vector<double> sums, sizes;
    for (const double value : values) {
        sums.push_back(value);
        sizes.push_back(1);
        while (sums.size() > 1 &&
               sums[sums.size() - 2] / sizes[sizes.size() - 2] > sums.back() / sizes.back()) {
            sums[sums.size() - 2] += sums.back();
            sizes[sizes.size() - 2] += sizes.back();
            sums.pop_back();
            sizes.pop_back();
        }
    }
    std::size_t code = 0;
    for (std::size_t block = 0; block < sums.size(); ++block) {
        for (int i = 0; i < static_cast<int>(sizes[block]); ++i) {
            values[code++] = sums[block] / sizes[block];
        }
    }
}

// OpenCV's curve, exp(g), made into a table (`seen`: the codes its samples show in this
// channel). OpenCV fits g over every code, but only the codes the samples show are measured:
// beyond them its smoothness term continues g as a straight line, an exponential in the code,
// while an ISP's encoding is close to a power law there (a gamma, sRGB's upper part). And code
// 255 is where the sensor clips, so its samples say only "at least this much light" and pull
// g(255) up, and its neighbours with it through the smoothness term. So above the highest code
// the samples show below 255, the table continues as the power law fitted (log–log least
// squares) to the top third of the codes up to there: code 255, whose value sets the scale of
// the whole table, is extrapolated from where the data are. Below the lowest code shown it
// falls as the power law of the few codes above, to 0 at code 0. Last, the read noise's
// wiggles at the dark end are made monotone (pool adjacent violators) and the table is divided
// by its top code's value.
std::vector<double> shapeTable(std::vector<double> table, const std::vector<bool>& seen,
                               int channel, int channels) {
    // exp(g) > 0, but a float can underflow where the curve plunges below the data.
    for (double& value : table) {
        value = std::max(value, 1e-30);
    }
    int top = kEightBitMax - 1, bottom = 0;
    while (top > 0 && !seen[static_cast<std::size_t>(top)]) {
        --top;
    }
    while (bottom < kEightBitMax && !seen[static_cast<std::size_t>(bottom)]) {
        ++bottom;
    }
    if (top - bottom < kMinCodeSpan) {
        throw common::InputError("bracket: " +
                                 (channels == 1
                                      ? std::string("the images show")
                                      : "channel " + channelName(channel, channels) + " shows") +
                                 " codes " + std::to_string(bottom) + ".." + std::to_string(top) +
                                 " only below the clip; a response needs at least " +
                                 std::to_string(kMinCodeSpan) + " codes from dark to bright");
    }
    const PowerLaw upper = fitPowerLaw(table, std::max(1, top * 2 / 3), top);
    for (int code = top + 1; code <= kEightBitMax; ++code) {
        table[static_cast<std::size_t>(code)] = upper.at(code);
    }
    if (bottom > 0) {
        const PowerLaw lower =
            fitPowerLaw(table, bottom, std::min(top, std::max(bottom + 4, bottom * 3 / 2)));
        const double anchor = table[static_cast<std::size_t>(bottom)];
        for (int code = 0; code < bottom; ++code) {
            table[static_cast<std::size_t>(code)] =
                anchor * std::pow(static_cast<double>(code) / bottom, lower.exponent);
        }
    }
    makeMonotone(table);
    const double scale = table.back();
    for (double& value : table) {
        value /= scale;
    }
    return table;
}

}  // namespace

CameraLinearization::CameraLinearization(std::vector<std::vector<double>> tables)
    : tables_(std::move(tables)) {
    const double top = maxValue();
    linear_ = std::all_of(tables_.begin(), tables_.end(), [top](const std::vector<double>& t) {
        for (std::size_t code = 0; code < t.size(); ++code) {
            if (std::abs(t[code] - static_cast<double>(code) / top) > 1e-12) {
                return false;
            }
        }
        return true;
    });
}

CameraLinearization CameraLinearization::identity(int maxValue, int channels) {
    if (maxValue < 1 || (channels != 1 && channels != 3)) {
        throw std::invalid_argument("camera linearization: identity of maxValue " +
                                    std::to_string(maxValue) + " and " + channelsOf(channels));
    }
    std::vector<double> table(static_cast<std::size_t>(maxValue) + 1);
    for (int code = 0; code <= maxValue; ++code) {
        table[static_cast<std::size_t>(code)] = static_cast<double>(code) / maxValue;
    }
    return CameraLinearization(
        std::vector<std::vector<double>>(static_cast<std::size_t>(channels), table));
}

CameraLinearization CameraLinearization::fromTables(std::vector<std::vector<double>> tables) {
    const int channels = static_cast<int>(tables.size());
    if (channels != 1 && channels != 3) {
        throw common::InputError("camera response: " + channelsOf(channels) +
                                 "; 1 (monochrome) or 3 (RGB) are needed");
    }
    const std::size_t size = tables.front().size();
    for (int c = 0; c < channels; ++c) {
        const std::vector<double>& table = tables[static_cast<std::size_t>(c)];
        const std::string name = "camera response: " + channelName(c, channels);
        if (table.size() != size || size < 2) {
            throw common::InputError(name + " has " + std::to_string(table.size()) +
                                     " codes; every channel needs the same number, at least 2");
        }
        for (std::size_t code = 0; code < size; ++code) {
            const double value = table[code];
            const std::string where = name + ", code " + std::to_string(code) + ": ";
            if (!std::isfinite(value) || value < 0) {
                throw common::InputError(where + formatNumber(value) +
                                         " is not a finite number ≥ 0");
            }
            if (code > 0 && value < table[code - 1]) {
                throw common::InputError(where + formatNumber(value) + " is below the previous " +
                                         formatNumber(table[code - 1]) +
                                         "; the response must be monotone non-decreasing");
            }
        }
        if (table.back() != 1) {
            throw common::InputError(name + ": the top code is " + formatNumber(table.back()) +
                                     "; it must be 1 (the signal that reaches the top code)");
        }
        if (!(table.front() < 1)) {
            throw common::InputError(name + " is flat: every code is 1");
        }
    }
    return CameraLinearization(std::move(tables));
}

double CameraLinearization::linear(int channel, int code) const {
    const std::vector<double>& t = table(channel);
    if (code < 0 || code > maxValue()) {
        throw std::out_of_range("camera linearization: code " + std::to_string(code) +
                                " outside 0.." + std::to_string(maxValue()));
    }
    return t[static_cast<std::size_t>(code)];
}

const std::vector<double>& CameraLinearization::table(int channel) const {
    if (channel < 0 || channel >= channels()) {
        throw std::out_of_range("camera linearization: channel " + std::to_string(channel) +
                                " of " + std::to_string(channels()));
    }
    return tables_[static_cast<std::size_t>(channel)];
}

CameraLinearization fitCameraResponse(std::span<const BracketedImage> images) {
    checkBracket(images);
    const int channels = images.front().channels;
    const std::vector<std::size_t> pixels = chooseSamplePixels(images);
    const int count = static_cast<int>(pixels.size());

    // One row per image holding the chosen pixels, and as many samples as pixels: OpenCV's grid
    // (x_points = ⌊√(samples·cols/rows)⌋ = count columns a step of 1 apart, one row) then visits
    // each of them exactly once.
    std::vector<cv::Mat> rows;
    std::vector<float> times;
    double longest = 0;
    for (const BracketedImage& image : images) {
        longest = std::max(longest, image.exposure);
    }
    for (const BracketedImage& image : images) {
        cv::Mat row(1, count, CV_8UC(channels));
        std::uint8_t* out = row.ptr<std::uint8_t>(0);
        for (int i = 0; i < count; ++i) {
            for (int c = 0; c < channels; ++c) {
                out[i * channels + c] =
                    static_cast<std::uint8_t>(image.samples[pixels[static_cast<std::size_t>(i)] *
                                                                static_cast<std::size_t>(channels) +
                                                            static_cast<std::size_t>(c)]);
            }
        }
        rows.push_back(row);
        // Only ratios matter (the scene's radiances absorb the unit): relative to the longest,
        // so that microseconds and seconds are alike in float.
        times.push_back(static_cast<float>(image.exposure / longest));
    }

    cv::Mat response;
    cv::createCalibrateDebevec(count, kSmoothness, false)->process(rows, response, times);

    std::vector<std::vector<double>> tables;
    for (int c = 0; c < channels; ++c) {
        std::vector<double> table(kEightBitMax + 1);
        for (int code = 0; code <= kEightBitMax; ++code) {
            table[static_cast<std::size_t>(code)] =
                static_cast<double>(response.ptr<float>(code)[c]);
        }
        // The codes the chosen pixels show in this channel, the only ones the data constrain.
        std::vector<bool> seen(kEightBitMax + 1, false);
        for (const cv::Mat& row : rows) {
            const std::uint8_t* in = row.ptr<std::uint8_t>(0);
            for (int i = 0; i < count; ++i) {
                seen[in[i * channels + c]] = true;
            }
        }
        tables.push_back(shapeTable(std::move(table), seen, c, channels));
    }
    return CameraLinearization::fromTables(std::move(tables));
}

void writeCameraResponseCsv(const std::filesystem::path& path,
                            const CameraLinearization& response) {
    std::ostringstream csv;
    csv << "code";
    for (int c = 0; c < response.channels(); ++c) {
        csv << ',' << channelName(c, response.channels());
    }
    csv << '\n';
    for (int code = 0; code <= response.maxValue(); ++code) {
        csv << code;
        for (int c = 0; c < response.channels(); ++c) {
            csv << ',' << formatNumber(response.linear(c, code));
        }
        csv << '\n';
    }
    proto::writeTextFileAtomically(path, csv.str());
}

CameraLinearization readCameraResponseCsv(const std::filesystem::path& path) {
    const std::string contents = text::readTextFile(path, "camera response");
    std::vector<std::vector<double>> tables;
    std::size_t columns = 0;
    bool first = true;
    for (const text::Line& line : text::splitLines(contents)) {
        if (line.text.empty() || line.text.front() == '#') {
            continue;
        }
        std::vector<std::string_view> fields;
        for (std::string_view rest = line.text;;) {
            const std::size_t comma = rest.find(',');
            fields.push_back(text::trim(rest.substr(0, comma)));
            if (comma == std::string_view::npos) {
                break;
            }
            rest.remove_prefix(comma + 1);
        }
        const bool header = first && !text::parseNumber(fields.front());
        first = false;
        if (header) {
            continue;
        }
        if (columns == 0) {
            if (fields.size() != 2 && fields.size() != 4) {
                throw common::InputError(path, line.number,
                                         "expected code,value or code,r,g,b, found " +
                                             std::to_string(fields.size()) +
                                             (fields.size() == 1 ? " field" : " fields"));
            }
            columns = fields.size();
            tables.resize(columns - 1);
        } else if (fields.size() != columns) {
            throw common::InputError(path, line.number,
                                     "expected " + std::to_string(columns) +
                                         " fields like the rows " + "before, found " +
                                         std::to_string(fields.size()));
        }
        const std::size_t expectedCode = tables.front().size();
        const auto code = text::parseInteger(fields.front());
        if (!code || *code != static_cast<long>(expectedCode)) {
            throw common::InputError(path, line.number,
                                     "code '" + std::string(fields.front()) + "' where " +
                                         std::to_string(expectedCode) +
                                         " comes next (codes run 0, 1, … without gaps)");
        }
        for (std::size_t c = 0; c + 1 < columns; ++c) {
            const auto value = text::parseNumber(fields[c + 1]);
            if (!value) {
                throw common::InputError(
                    path, line.number,
                    channelName(static_cast<int>(c), static_cast<int>(columns - 1)) + " '" +
                        std::string(fields[c + 1]) + "' is not a number");
            }
            tables[c].push_back(*value);
        }
    }
    if (tables.empty()) {
        throw common::InputError(path, "no codes: expected code,value or code,r,g,b rows");
    }
    try {
        return CameraLinearization::fromTables(std::move(tables));
    } catch (const common::InputError& error) {
        // "camera response: g, code 17: …" becomes "PATH: g, code 17: …".
        const std::string message = error.what();
        const std::string prefix = "camera response: ";
        throw common::InputError(
            path, message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message);
    }
}

}  // namespace vpe::radiometry
