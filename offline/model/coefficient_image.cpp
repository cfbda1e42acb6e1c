// SPDX-License-Identifier: MIT
// Reading a model file into a CoefficientImage, in bands of rows.
#include "vpe/model/coefficient_image.h"

#include <algorithm>

#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::model {

CoefficientImage readCoefficientImage(const std::filesystem::path& model) {
    ModelReader reader(model);
    return readCoefficientImage(reader);
}

CoefficientImage readCoefficientImage(ModelReader& reader) {
    const ModelInfo& info = reader.info();
    CoefficientImage image;
    image.width = info.width;
    image.height = info.height;
    image.harmonics = info.harmonics;
    image.lambda = info.lambda;
    image.tilesU = info.tilesU;
    image.dims = 3 * proto::coefficientCount(info.harmonics);
    const std::size_t pixels = static_cast<std::size_t>(info.width) * info.height;
    image.values.resize(pixels * image.dims);
    image.valid.resize(pixels);
    if (info.detailNormals) {
        image.detail.resize(pixels * 3);
    }
    ModelRows rows;
    constexpr int kBand = 64;
    for (int y = 0; y < info.height; y += kBand) {
        const int count = std::min(kBand, info.height - y);
        reader.readRows(y, count, rows);
        const std::size_t first = static_cast<std::size_t>(y) * info.width;
        // ModelRows is [pixel][channel][k], the layout of CoefficientImage.
        std::copy(rows.coefficient.begin(), rows.coefficient.end(),
                  image.values.begin() + static_cast<std::ptrdiff_t>(first * image.dims));
        std::copy(rows.valid.begin(), rows.valid.end(),
                  image.valid.begin() + static_cast<std::ptrdiff_t>(first));
        if (!image.detail.empty()) {
            std::copy(rows.detail.begin(), rows.detail.end(),
                      image.detail.begin() + static_cast<std::ptrdiff_t>(first * 3));
        }
    }
    return image;
}

}  // namespace vpe::model
