// SPDX-License-Identifier: MIT
// Scan outputs: EXR through OpenImageIO, PLY through Open3D, the sheet through image/.
#include "vpe/scan/scan_files.h"

#include <algorithm>
#include <cmath>

#include <open3d/geometry/PointCloud.h>
#include <open3d/io/PointCloudIO.h>

#include "vpe/common/input_error.h"
#include "vpe/image/contact_sheet.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/srgb.h"

namespace vpe::scan {

namespace {

const std::vector<std::string> kChannels{"position.X", "position.Y", "position.Z", "normal.X",
                                         "normal.Y",   "normal.Z",   "confidence"};

// Status colours: decoded grey-green, then the reasons a pixel was not.
constexpr float kStatusColours[structured_light::kDecodeStatusCount][3] = {
    {0.55f, 0.85f, 0.55f},  // decoded
    {0.00f, 0.00f, 0.00f},  // dark
    {1.00f, 1.00f, 1.00f},  // saturated
    {0.90f, 0.20f, 0.20f},  // ambiguous (interreflection)
    {0.95f, 0.65f, 0.10f},  // low modulation
    {0.70f, 0.20f, 0.90f},  // inconsistent
    {0.20f, 0.45f, 0.95f},  // edge (mixed pixels)
};

}  // namespace

void writeSurface(const ProjectorSurface& s, const std::filesystem::path& path) {
    const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
    std::vector<float> values(pixels * kChannels.size());
    for (std::size_t p = 0; p < pixels; ++p) {
        float* v = &values[p * kChannels.size()];
        std::copy_n(&s.position[3 * p], 3, v);
        std::copy_n(&s.normal[3 * p], 3, v + 3);
        v[6] = s.confidence[p];
    }
    image::writeImage(path, s.width, s.height, static_cast<int>(kChannels.size()), values,
                      image::PixelFormat::kFloat, kChannels);
}

ProjectorSurface readSurface(const std::filesystem::path& path) {
    const image::FloatImage image = image::readImageChannels(path, kChannels);
    ProjectorSurface s;
    s.width = image.width;
    s.height = image.height;
    const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
    s.position.resize(pixels * 3);
    s.normal.resize(pixels * 3);
    s.confidence.resize(pixels);
    s.rayGap.assign(pixels, std::nanf(""));
    s.cameraU.assign(pixels, std::nanf(""));
    s.cameraV.assign(pixels, std::nanf(""));
    for (std::size_t p = 0; p < pixels; ++p) {
        const float* v = &image.pixels[p * kChannels.size()];
        std::copy_n(v, 3, &s.position[3 * p]);
        std::copy_n(v + 3, 3, &s.normal[3 * p]);
        s.confidence[p] = v[6];
        s.measured += std::isnan(v[0]) ? 0 : 1;
    }
    if (s.measured == 0) {
        throw common::InputError(path, "the scan measured nothing");
    }
    return s;
}

void writeDecoded(const structured_light::DecodedScan& d, const std::filesystem::path& path) {
    const std::vector<std::string> names{"projector.x", "projector.y", "status", "direct",
                                         "global",      "white",       "black",  "precision"};
    const std::size_t pixels = static_cast<std::size_t>(d.width) * d.height;
    std::vector<float> values(pixels * names.size());
    for (std::size_t p = 0; p < pixels; ++p) {
        float* v = &values[p * names.size()];
        v[0] = d.projectorX[p];
        v[1] = d.projectorY[p];
        v[2] = static_cast<float>(d.status[p]);
        v[3] = d.direct[p];
        v[4] = d.global[p];
        v[5] = d.white[p];
        v[6] = d.black[p];
        v[7] = d.precision[p];
    }
    image::writeImage(path, d.width, d.height, static_cast<int>(names.size()), values,
                      image::PixelFormat::kFloat, names);
}

void writePointCloud(const ProjectorSurface& s, const std::filesystem::path& path) {
    open3d::geometry::PointCloud cloud;
    const std::size_t pixels = static_cast<std::size_t>(s.width) * s.height;
    cloud.points_.reserve(s.measured);
    cloud.normals_.reserve(s.measured);
    cloud.colors_.reserve(s.measured);
    for (std::size_t p = 0; p < pixels; ++p) {
        if (std::isnan(s.position[3 * p])) {
            continue;
        }
        cloud.points_.emplace_back(s.position[3 * p], s.position[3 * p + 1], s.position[3 * p + 2]);
        cloud.normals_.emplace_back(s.normal[3 * p], s.normal[3 * p + 1], s.normal[3 * p + 2]);
        // Confidence as grey: viewers show it without knowing the property.
        const double c = s.confidence[p];
        cloud.colors_.emplace_back(c, c, c);
    }
    proto::AtomicFile output(path);
    open3d::io::WritePointCloudOption options;
    options.write_ascii = open3d::io::WritePointCloudOption::IsAscii::Binary;
    if (!open3d::io::WritePointCloudToPLY(output.temporaryPath().string(), cloud, options)) {
        throw common::InputError(path, "cannot write the point cloud");
    }
    output.commit();
}

void writeScanSheet(const structured_light::DecodedScan& d, const ProjectorSurface& s,
                    const std::filesystem::path& path) {
    std::vector<image::SheetTile> tiles;
    const std::size_t cameraPixels = static_cast<std::size_t>(d.width) * d.height;
    // The white frame, sRGB-encoded so a linear camera's picture looks as the eye expects.
    image::SheetTile white{"camera, white frame", d.width, d.height, 1, {}};
    white.pixels.resize(cameraPixels);
    for (std::size_t p = 0; p < cameraPixels; ++p) {
        white.pixels[p] =
            static_cast<float>(proto::linearToSrgb(std::clamp(double(d.white[p]), 0.0, 1.0)));
    }
    tiles.push_back(std::move(white));
    image::SheetTile status{
        "decoded (green); dark; saturated; ambiguous (red); weak (orange); "
        "inconsistent (violet); edge (blue)",
        d.width,
        d.height,
        3,
        {}};
    status.pixels.resize(cameraPixels * 3);
    for (std::size_t p = 0; p < cameraPixels; ++p) {
        std::copy_n(kStatusColours[static_cast<int>(d.status[p])], 3, &status.pixels[3 * p]);
    }
    tiles.push_back(std::move(status));
    tiles.push_back(image::scalarTile("projector x decoded", d.width, d.height, d.projectorX, 0,
                                      float(d.projectorWidth)));
    tiles.push_back(image::scalarTile("projector y decoded", d.width, d.height, d.projectorY, 0,
                                      float(d.projectorHeight)));
    const std::size_t projectorPixels = static_cast<std::size_t>(s.width) * s.height;
    std::vector<float> depth(projectorPixels, std::nanf(""));
    float nearest = INFINITY, furthest = -INFINITY;
    for (std::size_t p = 0; p < projectorPixels; ++p) {
        if (!std::isnan(s.position[3 * p])) {
            depth[p] = s.position[3 * p + 2];
            nearest = std::min(nearest, depth[p]);
            furthest = std::max(furthest, depth[p]);
        }
    }
    tiles.push_back(image::scalarTile("depth (camera z), projector's view", s.width, s.height,
                                      depth, nearest, furthest));
    image::SheetTile normals{"normals, projector's view", s.width, s.height, 3, {}};
    normals.pixels.resize(projectorPixels * 3);
    for (std::size_t p = 0; p < projectorPixels * 3; ++p) {
        normals.pixels[p] = std::isnan(s.normal[p]) ? 0.0f : 0.5f + 0.5f * s.normal[p];
    }
    tiles.push_back(std::move(normals));
    tiles.push_back(image::scalarTile("confidence", s.width, s.height, s.confidence, 0, 1));
    image::writeContactSheet(path, tiles, 4);
}

}  // namespace vpe::scan
