// SPDX-License-Identifier: MIT
// Normal source selection.
#include "vpe/normals/normal_source.h"

#include "vpe/common/input_error.h"
#include "vpe/normals/photometric_stereo.h"

namespace vpe::normals {

NormalsResult acquireNormals(const capture::Capture& capture,
                             const std::optional<std::filesystem::path>& overridePath, int width,
                             int height, unsigned threads) {
    NormalsResult result;
    std::optional<std::filesystem::path> file = overridePath ? overridePath : capture.normalMap;
    if (file) {
        result.normals = readNormalMap(
            *file, overridePath ? capture::NormalEncoding::kAuto : capture.normalEncoding);
        result.source = file->string();
        if (result.normals.width != width || result.normals.height != height) {
            throw common::InputError(
                *file, "normal map size " + std::to_string(result.normals.width) + "x" +
                           std::to_string(result.normals.height) + " differs from the images' " +
                           std::to_string(width) + "x" + std::to_string(height));
        }
        return result;
    }
    PhotometricStereoOptions options;
    options.threads = threads;
    result.normals = estimateNormals(capture, options);
    result.source = "photometric stereo";
    result.estimated = true;
    return result;
}

}  // namespace vpe::normals
