// SPDX-License-Identifier: MIT
// Normal map I/O and comparison.
#include "vpe/normals/normal_map.h"

#include <algorithm>
#include <cmath>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::normals {

NormalMap readNormalMap(const std::filesystem::path& path, capture::NormalEncoding encoding) {
    const image::FloatImage image = image::readImage(path);
    if (image.channels < 3) {
        throw common::InputError(
            path, "normal map needs 3 channels, found " + std::to_string(image.channels));
    }
    const bool offset = encoding == capture::NormalEncoding::kOffsetRgb ||
                        (encoding == capture::NormalEncoding::kAuto && image.integerSource);
    NormalMap normals;
    normals.resize(image.width, image.height);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            float n[3];
            for (int c = 0; c < 3; ++c) {
                const float v = image.at(x, y, c);
                n[c] = offset ? 2.0f * v - 1.0f : v;
            }
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            const std::size_t i = normals.index(x, y);
            // Quantized unit normals stay within a few percent of length 1; anything else
            // (black background decodes to length √3) is not a normal.
            if (std::isfinite(length) && length > 0.5f && length < 1.5f) {
                for (int c = 0; c < 3; ++c) {
                    normals.xyz[i * 3 + c] = n[c] / length;
                }
                normals.valid[i] = 1;
            }
        }
    }
    return normals;
}

void writeNormalMapPng(const std::filesystem::path& path, const NormalMap& normals) {
    std::vector<std::uint8_t> pixels(normals.xyz.size());
    for (std::size_t i = 0; i < normals.valid.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const float v = normals.valid[i] ? (normals.xyz[i * 3 + c] + 1.0f) * 0.5f : 0.0f;
            pixels[i * 3 + c] =
                static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255));
        }
    }
    image::writeImage8(path, normals.width, normals.height, 3, pixels);
}

AngularError compareNormalMaps(const NormalMap& estimate, const NormalMap& truth) {
    AngularError result;
    if (estimate.width != truth.width || estimate.height != truth.height) {
        throw common::InputError("normal maps differ in size: " + std::to_string(estimate.width) +
                                 "x" + std::to_string(estimate.height) + " vs " +
                                 std::to_string(truth.width) + "x" + std::to_string(truth.height));
    }
    std::vector<double> angles;
    for (std::size_t i = 0; i < truth.valid.size(); ++i) {
        if (!estimate.valid[i] || !truth.valid[i]) {
            continue;
        }
        double d = 0;
        for (int c = 0; c < 3; ++c) {
            d += static_cast<double>(estimate.xyz[i * 3 + c]) *
                 static_cast<double>(truth.xyz[i * 3 + c]);
        }
        angles.push_back(std::acos(std::clamp(d, -1.0, 1.0)) * 180.0 / M_PI);
    }
    result.pixels = angles.size();
    if (angles.empty()) {
        return result;
    }
    double sum = 0;
    for (double a : angles) {
        sum += a;
    }
    result.meanDegrees = sum / static_cast<double>(angles.size());
    std::nth_element(angles.begin(), angles.begin() + static_cast<long>(angles.size() / 2),
                     angles.end());
    result.medianDegrees = angles[angles.size() / 2];
    return result;
}

}  // namespace vpe::normals
