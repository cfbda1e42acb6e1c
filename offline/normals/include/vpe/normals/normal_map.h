// SPDX-License-Identifier: MIT
// NormalMap: one unit normal per pixel in the capture's world frame, with a validity flag.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::normals {

struct NormalMap {
    int width = 0;
    int height = 0;
    std::vector<float> xyz;           // 3 per pixel
    std::vector<std::uint8_t> valid;  // 1 per pixel

    void resize(int w, int h) {
        width = w;
        height = h;
        xyz.assign(static_cast<std::size_t>(w) * h * 3, 0.0f);
        valid.assign(static_cast<std::size_t>(w) * h, 0);
    }
    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
    bool validAt(int x, int y) const { return valid[index(x, y)] != 0; }
    proto::Vec3d at(int x, int y) const {
        const std::size_t i = index(x, y) * 3;
        return {xyz[i], xyz[i + 1], xyz[i + 2]};
    }
};

// Reads a normal map. kAuto: integer images are (n + 1)/2, floating-point images hold n.
// Pixels whose decoded vector is far from unit length (e.g. black background) are invalid.
NormalMap readNormalMap(const std::filesystem::path& path, capture::NormalEncoding encoding);

// Writes (n + 1)/2 as 8-bit RGB; invalid pixels are black.
void writeNormalMapPng(const std::filesystem::path& path, const NormalMap& normals);

struct AngularError {
    double meanDegrees = 0;
    double medianDegrees = 0;
    std::size_t pixels = 0;  // valid in both maps
};

AngularError compareNormalMaps(const NormalMap& estimate, const NormalMap& truth);

}  // namespace vpe::normals
