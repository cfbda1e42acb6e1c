// SPDX-License-Identifier: MIT
// Region map names and the positions file (multi-part OpenEXR through OpenImageIO).
#include "vpe/quilt/quilt_folder.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <OpenImageIO/imageio.h>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::quilt {

namespace {

constexpr const char* kPositionChannels[3] = {"source.x", "source.y", "region"};

std::string pixelName(int x, int y) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

}  // namespace

std::filesystem::path regionMapPath(const std::filesystem::path& dir, int region) {
    return dir / ("region" + std::to_string(region) + ".exr");
}

std::filesystem::path positionsPath(const std::filesystem::path& dir, int region) {
    return dir / ("positions" + std::to_string(region) + ".exr");
}

std::vector<std::filesystem::path> listRegionMaps(const std::filesystem::path& dir) {
    std::error_code error;
    if (!std::filesystem::is_directory(dir, error)) {
        throw common::InputError(dir, "no such folder (expected the output of vpe quilt)");
    }
    // The highest index present, so a gap is reported rather than silently ending the list.
    int highest = -1;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (!name.starts_with("region") || entry.path().extension() != ".exr") {
            continue;
        }
        const std::string digits = name.substr(6, name.size() - 6 - 4);
        if (digits.empty() || digits.size() > 3 || (digits.size() > 1 && digits[0] == '0') ||
            !std::all_of(digits.begin(), digits.end(),
                         [](char c) { return c >= '0' && c <= '9'; })) {
            continue;
        }
        highest = std::max(highest, std::stoi(digits));
    }
    if (highest < 0) {
        throw common::InputError(dir,
                                 "no region0.exr (expected region0.exr, region1.exr, ... from vpe "
                                 "quilt)");
    }
    std::vector<std::filesystem::path> maps;
    for (int k = 0; k <= highest; ++k) {
        std::filesystem::path path = regionMapPath(dir, k);
        if (!std::filesystem::exists(path)) {
            throw common::InputError(
                path, "missing, but region" + std::to_string(highest) +
                          ".exr exists (region maps are numbered from 0 without gaps)");
        }
        maps.push_back(std::move(path));
    }
    return maps;
}

void PositionMap::resize(int w, int h) {
    width = w;
    height = h;
    sourceX.assign(static_cast<std::size_t>(w) * h, -1);
    sourceY.assign(static_cast<std::size_t>(w) * h, -1);
}

void writePositionMap(const std::filesystem::path& path, const PositionMap& map, int region) {
    const std::size_t count = static_cast<std::size_t>(map.width) * map.height;
    std::vector<float> pixels(count * 3);
    for (std::size_t p = 0; p < count; ++p) {
        pixels[p * 3 + 0] = static_cast<float>(map.sourceX[p]);
        pixels[p * 3 + 1] = static_cast<float>(map.sourceY[p]);
        pixels[p * 3 + 2] = static_cast<float>(region);
    }
    image::writeImage(path, map.width, map.height, 3, pixels, image::PixelFormat::kFloat,
                      {std::begin(kPositionChannels), std::end(kPositionChannels)});
}

namespace {

// Adds every subimage of one positions file to the maps of the regions its pixels name.
void readPositionFile(const std::filesystem::path& path, std::vector<PositionMap>& maps,
                      int sourceWidth, int sourceHeight) {
    auto input = OIIO::ImageInput::open(path.string());
    if (!input) {
        throw common::InputError(path, "cannot read positions: " + OIIO::geterror());
    }
    const int regions = static_cast<int>(maps.size());
    const int width = maps[0].width, height = maps[0].height;
    std::vector<float> pixels;
    for (int subimage = 0; input->seek_subimage(subimage, 0); ++subimage) {
        const OIIO::ImageSpec& spec = input->spec();
        const std::string part = subimage > 0 ? " (subimage " + std::to_string(subimage) + ")" : "";
        if (spec.width != width || spec.height != height) {
            throw common::InputError(
                path, "size " + std::to_string(spec.width) + " × " + std::to_string(spec.height) +
                          part + " differs from the region maps' " + std::to_string(width) + " × " +
                          std::to_string(height));
        }
        int channel[3];
        for (int c = 0; c < 3; ++c) {
            const auto it =
                std::find(spec.channelnames.begin(), spec.channelnames.end(), kPositionChannels[c]);
            if (it == spec.channelnames.end()) {
                throw common::InputError(
                    path, std::string("missing channel '") + kPositionChannels[c] + "'" + part);
            }
            channel[c] = static_cast<int>(it - spec.channelnames.begin());
        }
        const int channels = spec.nchannels;
        pixels.resize(static_cast<std::size_t>(width) * height * channels);
        if (!input->read_image(subimage, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data())) {
            throw common::InputError(path,
                                     "cannot decode positions" + part + ": " + input->geterror());
        }
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * width + x;
                long value[3];
                for (int c = 0; c < 3; ++c) {
                    const float v = pixels[p * channels + channel[c]];
                    if (!std::isfinite(v) || v != std::round(v) || std::fabs(v) > 1e7f) {
                        throw common::InputError(
                            path, pixelName(x, y) + part + ": " + kPositionChannels[c] + " = " +
                                      std::to_string(v) + " is not an integer");
                    }
                    value[c] = std::lround(v);
                }
                if (value[0] == -1 && value[1] == -1) {
                    continue;  // no position: the quilter did not copy this pixel
                }
                if (value[2] < 0 || value[2] >= regions) {
                    throw common::InputError(
                        path, pixelName(x, y) + part + ": region " + std::to_string(value[2]) +
                                  " but there are " + std::to_string(regions) + " region maps");
                }
                if (value[0] < 0 || value[0] >= sourceWidth || value[1] < 0 ||
                    value[1] >= sourceHeight) {
                    throw common::InputError(
                        path, pixelName(x, y) + part + ": source (" + std::to_string(value[0]) +
                                  ", " + std::to_string(value[1]) + ") is outside the " +
                                  std::to_string(sourceWidth) + " × " +
                                  std::to_string(sourceHeight) + " source model");
                }
                PositionMap& map = maps[static_cast<std::size_t>(value[2])];
                if (map.known(p)) {
                    throw common::InputError(path, pixelName(x, y) + part + ": region " +
                                                       std::to_string(value[2]) +
                                                       " has this pixel's position twice");
                }
                map.sourceX[p] = static_cast<std::int32_t>(value[0]);
                map.sourceY[p] = static_cast<std::int32_t>(value[1]);
            }
        }
    }
}

}  // namespace

std::vector<PositionMap> readPositionMaps(const std::filesystem::path& dir, int regions, int width,
                                          int height, int sourceWidth, int sourceHeight) {
    std::vector<std::filesystem::path> files;
    for (int k = 0; k < regions; ++k) {
        if (std::filesystem::exists(positionsPath(dir, k))) {
            files.push_back(positionsPath(dir, k));
        }
    }
    if (std::filesystem::exists(dir / "positions.exr")) {
        files.push_back(dir / "positions.exr");
    }
    if (files.empty()) {
        throw common::InputError(positionsPath(dir, 0),
                                 "no such positions file (vpe quilt writes "
                                 "positions<k>.exr next to region<k>.exr)");
    }
    std::vector<PositionMap> maps(static_cast<std::size_t>(regions));
    for (PositionMap& map : maps) {
        map.resize(width, height);
    }
    for (const auto& file : files) {
        readPositionFile(file, maps, sourceWidth, sourceHeight);
    }
    return maps;
}

}  // namespace vpe::quilt
