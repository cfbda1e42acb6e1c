// SPDX-License-Identifier: MIT
// Seeded labelling, island removal, label order and the label pictures.
#include "vpe/segment/label_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/luminance.h"
#include "vpe/proto/srgb.h"

namespace vpe::segment {

namespace {

double luminance(const float* rgb) {
    return proto::luminance709(rgb[0], rgb[1], rgb[2]);
}

// Distinct colours for any number of labels: hues a golden angle apart, value alternating so
// neighbours in the sequence differ in brightness too.
std::array<double, 3> paletteColour(int label) {
    const double hue = std::fmod(0.08 + label * 0.6180339887498949, 1.0) * 6.0;
    const double saturation = 0.8;
    const double value = label % 2 == 0 ? 1.0 : 0.7;
    const int sector = static_cast<int>(hue) % 6;
    const double f = hue - std::floor(hue);
    const double p = value * (1 - saturation), q = value * (1 - saturation * f),
                 t = value * (1 - saturation * (1 - f));
    switch (sector) {
        case 0:
            return {value, t, p};
        case 1:
            return {q, value, p};
        case 2:
            return {p, value, t};
        case 3:
            return {p, q, value};
        case 4:
            return {t, p, value};
        default:
            return {value, p, q};
    }
}

// Connected components of equal labels (4-connectivity); pixels without a label get −1.
struct Components {
    std::vector<int> id;                           // [pixel]
    std::vector<std::vector<std::size_t>> pixels;  // [component]
};

Components findComponents(const LabelMap& map) {
    Components components;
    components.id.assign(map.values.size(), -1);
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < map.values.size(); ++start) {
        if (map.values[start] == LabelMap::kNoLabel || components.id[start] >= 0) {
            continue;
        }
        const int id = static_cast<int>(components.pixels.size());
        components.pixels.emplace_back();
        std::vector<std::size_t>& members = components.pixels.back();
        const std::uint8_t label = map.values[start];
        components.id[start] = id;
        stack.push_back(start);
        while (!stack.empty()) {
            const std::size_t p = stack.back();
            stack.pop_back();
            members.push_back(p);
            const int x = static_cast<int>(p % static_cast<std::size_t>(map.width));
            const int y = static_cast<int>(p / static_cast<std::size_t>(map.width));
            const std::size_t w = static_cast<std::size_t>(map.width);
            const std::size_t neighbours[4] = {x > 0 ? p - 1 : p, x + 1 < map.width ? p + 1 : p,
                                               y > 0 ? p - w : p, y + 1 < map.height ? p + w : p};
            for (std::size_t q : neighbours) {
                if (q != p && components.id[q] < 0 && map.values[q] == label) {
                    components.id[q] = id;
                    stack.push_back(q);
                }
            }
        }
    }
    return components;
}

}  // namespace

LabelMap labelBySeeds(const Appearance& appearance, const std::vector<PixelSeed>& seeds,
                      SeedSpace space) {
    LabelMap map;
    map.width = appearance.width;
    map.height = appearance.height;
    map.labels = static_cast<int>(seeds.size());
    map.values.assign(appearance.valid.size(), LabelMap::kNoLabel);
    const bool colour = space == SeedSpace::kColour;
    const std::size_t dims = colour ? 3 : static_cast<std::size_t>(appearance.featureCount);
    const std::vector<float>& values = colour ? appearance.lab : appearance.features;
    // A seed stands for the mean over the valid pixels of a small window around it: a click
    // lands on one pixel, but means the material there, not that pixel's noise.
    constexpr int kSeedRadius = 2;
    std::vector<double> seedValues(seeds.size() * dims, 0.0);
    for (std::size_t s = 0; s < seeds.size(); ++s) {
        double count = 0;
        for (int y = seeds[s].y - kSeedRadius; y <= seeds[s].y + kSeedRadius; ++y) {
            for (int x = seeds[s].x - kSeedRadius; x <= seeds[s].x + kSeedRadius; ++x) {
                if (x < 0 || y < 0 || x >= appearance.width || y >= appearance.height ||
                    !appearance.valid[appearance.pixel(x, y)]) {
                    continue;
                }
                const float* v = &values[appearance.pixel(x, y) * dims];
                for (std::size_t d = 0; d < dims; ++d) {
                    seedValues[s * dims + d] += static_cast<double>(v[d]);
                }
                count += 1;
            }
        }
        for (std::size_t d = 0; d < dims; ++d) {
            seedValues[s * dims + d] /= count;  // the seed pixel itself is valid: count ≥ 1
        }
    }
    for (std::size_t p = 0; p < appearance.valid.size(); ++p) {
        if (!appearance.valid[p]) {
            continue;
        }
        const float* v = &values[p * dims];
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t s = 0; s < seeds.size(); ++s) {
            double d = 0;
            for (std::size_t c = 0; c < dims; ++c) {
                const double difference = static_cast<double>(v[c]) - seedValues[s * dims + c];
                d += difference * difference;
            }
            if (d < best) {
                best = d;
                map.values[p] = static_cast<std::uint8_t>(s);
            }
        }
    }
    return map;
}

std::size_t removeIslands(LabelMap& map, std::size_t minArea) {
    std::size_t merged = 0;
    // Each pass merges every small region that has a neighbour; a merge only ever joins
    // regions, so the passes end (bounded for safety).
    for (int pass = 0; pass < 64; ++pass) {
        const Components components = findComponents(map);
        std::vector<int> small;
        for (std::size_t c = 0; c < components.pixels.size(); ++c) {
            if (components.pixels[c].size() < minArea) {
                small.push_back(static_cast<int>(c));
            }
        }
        std::stable_sort(small.begin(), small.end(), [&](int a, int b) {
            return components.pixels[static_cast<std::size_t>(a)].size() <
                   components.pixels[static_cast<std::size_t>(b)].size();
        });
        std::size_t mergedThisPass = 0;
        std::vector<std::size_t> votes(LabelMap::kMaxLabels + 1);
        const std::size_t w = static_cast<std::size_t>(map.width);
        for (int c : small) {
            const std::vector<std::size_t>& members =
                components.pixels[static_cast<std::size_t>(c)];
            const std::uint8_t own = map.values[members.front()];
            std::fill(votes.begin(), votes.end(), 0);
            bool any = false;
            for (std::size_t p : members) {
                const int x = static_cast<int>(p % w);
                const int y = static_cast<int>(p / w);
                const std::size_t neighbours[4] = {x > 0 ? p - 1 : p, x + 1 < map.width ? p + 1 : p,
                                                   y > 0 ? p - w : p,
                                                   y + 1 < map.height ? p + w : p};
                for (std::size_t q : neighbours) {
                    const std::uint8_t label = map.values[q];
                    if (q != p && label != own && label != LabelMap::kNoLabel) {
                        ++votes[label];
                        any = true;
                    }
                }
            }
            if (!any) {
                continue;
            }
            const std::uint8_t winner = static_cast<std::uint8_t>(
                std::max_element(votes.begin(), votes.end()) - votes.begin());
            for (std::size_t p : members) {
                map.values[p] = winner;
            }
            ++mergedThisPass;
        }
        merged += mergedThisPass;
        if (mergedThisPass == 0) {
            break;
        }
    }
    return merged;
}

std::vector<std::size_t> labelAreas(const LabelMap& map) {
    std::vector<std::size_t> areas(static_cast<std::size_t>(std::max(map.labels, 0)), 0);
    for (std::uint8_t v : map.values) {
        if (v != LabelMap::kNoLabel && v < areas.size()) {
            ++areas[v];
        }
    }
    return areas;
}

void orderLabelsByLuminance(LabelMap& map, const Appearance& appearance) {
    std::vector<double> sum(LabelMap::kMaxLabels, 0.0);
    std::vector<std::size_t> count(LabelMap::kMaxLabels, 0);
    for (std::size_t p = 0; p < map.values.size(); ++p) {
        if (map.values[p] != LabelMap::kNoLabel) {
            sum[map.values[p]] += luminance(&appearance.average[p * 3]);
            ++count[map.values[p]];
        }
    }
    std::vector<int> used;
    for (int label = 0; label < LabelMap::kMaxLabels; ++label) {
        if (count[static_cast<std::size_t>(label)] > 0) {
            used.push_back(label);
        }
    }
    auto mean = [&](int label) {
        return sum[static_cast<std::size_t>(label)] /
               static_cast<double>(count[static_cast<std::size_t>(label)]);
    };
    std::stable_sort(used.begin(), used.end(), [&](int a, int b) { return mean(a) < mean(b); });
    std::vector<std::uint8_t> renumber(LabelMap::kMaxLabels + 1, LabelMap::kNoLabel);
    for (std::size_t i = 0; i < used.size(); ++i) {
        renumber[static_cast<std::size_t>(used[i])] = static_cast<std::uint8_t>(i);
    }
    for (std::uint8_t& v : map.values) {
        v = renumber[v];
    }
    map.labels = static_cast<int>(used.size());
}

LabelMap readLabelImage(const std::filesystem::path& path) {
    const image::FloatImage image = image::readImage(path);
    if (!image.integerSource) {
        throw common::InputError(path, "not a label image (8-bit integer values expected)");
    }
    LabelMap map;
    map.width = image.width;
    map.height = image.height;
    map.values.resize(static_cast<std::size_t>(image.width) * image.height);
    int highest = -1;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const double scaled = static_cast<double>(image.at(x, y, 0)) * 255.0;
            const long value = std::lround(scaled);
            const std::string where =
                " (pixel " + std::to_string(x) + ", " + std::to_string(y) + ")";
            // A 16-bit image's values fall between the 8-bit steps.
            if (std::fabs(scaled - static_cast<double>(value)) > 1e-3 || value < 0 || value > 255) {
                throw common::InputError(path, "not an 8-bit label image" + where);
            }
            // A grey label image saved as RGB by an editor still carries the labels; an image
            // whose channels differ is a picture, not labels.
            for (int c = 1; c < std::min(image.channels, 3); ++c) {
                if (image.at(x, y, c) != image.at(x, y, 0)) {
                    throw common::InputError(path,
                                             "not a label image: its channels differ" + where);
                }
            }
            map.values[static_cast<std::size_t>(y) * image.width + x] =
                static_cast<std::uint8_t>(value);
            if (value != LabelMap::kNoLabel) {
                highest = std::max(highest, static_cast<int>(value));
            }
        }
    }
    map.labels = highest + 1;
    return map;
}

LabelMap readLabelImage(const std::filesystem::path& path, int width, int height) {
    LabelMap map = readLabelImage(path);
    if (map.width != width || map.height != height) {
        throw common::InputError(path, "labels are " + std::to_string(map.width) + "x" +
                                           std::to_string(map.height) + " but the model is " +
                                           std::to_string(width) + "x" + std::to_string(height));
    }
    return map;
}

void writeLabelImage(const std::filesystem::path& path, const LabelMap& map) {
    image::writeImage8(path, map.width, map.height, 1, map.values);
}

std::vector<std::uint8_t> averagePicture(const Appearance& appearance) {
    std::vector<float> brightest;
    for (std::size_t p = 0; p < appearance.valid.size(); ++p) {
        if (appearance.valid[p]) {
            const float* rgb = &appearance.average[p * 3];
            brightest.push_back(std::max({rgb[0], rgb[1], rgb[2]}));
        }
    }
    double white = 1.0;
    if (!brightest.empty()) {
        const std::size_t at = brightest.size() * 99 / 100;
        std::nth_element(brightest.begin(), brightest.begin() + static_cast<std::ptrdiff_t>(at),
                         brightest.end());
        white =
            static_cast<double>(brightest[at]) > 1e-9 ? static_cast<double>(brightest[at]) : 1.0;
    }
    std::vector<std::uint8_t> picture(appearance.average.size(), 0);
    for (std::size_t i = 0; i < picture.size(); ++i) {
        const double linear =
            std::clamp(static_cast<double>(appearance.average[i]) / white, 0.0, 1.0);
        picture[i] = static_cast<std::uint8_t>(std::lround(proto::linearToSrgb(linear) * 255));
    }
    return picture;
}

void writeLabelOverlay(const std::filesystem::path& path, const LabelMap& map,
                       const Appearance& appearance) {
    std::vector<std::uint8_t> picture = averagePicture(appearance);
    const std::size_t w = static_cast<std::size_t>(map.width);
    for (std::size_t p = 0; p < map.values.size(); ++p) {
        const std::uint8_t label = map.values[p];
        if (label == LabelMap::kNoLabel) {
            continue;
        }
        const int x = static_cast<int>(p % w);
        const int y = static_cast<int>(p / w);
        const bool boundary = (x + 1 < map.width && map.values[p + 1] != label) ||
                              (y + 1 < map.height && map.values[p + w] != label) ||
                              (x > 0 && map.values[p - 1] != label) ||
                              (y > 0 && map.values[p - w] != label);
        const std::array<double, 3> colour = paletteColour(label);
        for (int c = 0; c < 3; ++c) {
            std::uint8_t& out = picture[p * 3 + static_cast<std::size_t>(c)];
            const double blended =
                boundary ? 255.0 : 0.55 * out + 0.45 * 255.0 * colour[static_cast<std::size_t>(c)];
            out = static_cast<std::uint8_t>(std::lround(std::clamp(blended, 0.0, 255.0)));
        }
    }
    image::writeImage8(path, map.width, map.height, 3, picture);
}

std::filesystem::path overlayPathFor(const std::filesystem::path& labels) {
    std::filesystem::path overlay = labels;
    overlay.replace_filename(labels.stem().string() + "-overlay" + labels.extension().string());
    return overlay;
}

}  // namespace vpe::segment
