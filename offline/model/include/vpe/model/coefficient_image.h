// SPDX-License-Identifier: MIT
// CoefficientImage: a model in memory, what the quilt, its quality measures and the bake work
// on. Every pixel's coefficients are one vector, [channel][k] as the model file's rows hold
// them, so that quilting copies a pixel as a whole and the bake reorders it once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace vpe::model {

struct CoefficientImage {
    int width = 0;
    int height = 0;
    // Values per pixel: 3K for a model (K = 2M + 2 coefficients per colour channel). The
    // quilter takes any vector per pixel, such as a signed distance (dims 1, harmonics 0).
    int dims = 0;
    int harmonics = 0;
    double lambda = 0;
    bool tilesU = false;        // the model file says it tiles in u (vpe quilt on a wrapping mesh)
    std::vector<float> values;  // [(y·width + x)·dims + c·K + k]
    std::vector<std::uint8_t> valid;  // per pixel (a quilter's source in memory may leave it empty)
    // The relief's detail normal per pixel as the model file stores it ([pixel][3], tangent
    // space, proto/detail_normal.h); empty when the model has none.
    std::vector<float> detail;

    std::size_t pixel(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
    const float* at(std::size_t pixel) const { return values.data() + pixel * dims; }
    const float* at(int x, int y) const { return at(pixel(x, y)); }
};

// Reads a whole model file (vpe fit, quilt, compose): coefficients, flags and relief, as
// stored (an invalid pixel's values are whatever the file holds).
CoefficientImage readCoefficientImage(const std::filesystem::path& model);

class ModelReader;
// The same from a reader already open (its rows not yet read).
CoefficientImage readCoefficientImage(ModelReader& reader);

}  // namespace vpe::model
