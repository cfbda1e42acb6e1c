// SPDX-License-Identifier: MIT
// Contact sheets through OpenImageIO's ImageBufAlgo: resize, text (FreeType, DejaVu), paste.
#include "vpe/image/contact_sheet.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"

namespace vpe::image {

namespace {

// Debian's fonts-dejavu-core (scripts/install-deps.sh): the scripts' pictures use it too.
constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr int kPad = 4;

}  // namespace

void writeContactSheet(const std::filesystem::path& path, const std::vector<SheetTile>& tiles,
                       int columns, int tileWidth) {
    if (tiles.empty() || columns < 1) {
        throw common::InputError(path, "a contact sheet needs tiles");
    }
    std::vector<OIIO::ImageBuf> scaled;
    int rowHeight = 0;
    for (const SheetTile& tile : tiles) {
        OIIO::ImageBuf source(
            OIIO::ImageSpec(tile.width, tile.height, tile.channels, OIIO::TypeDesc::FLOAT),
            const_cast<float*>(tile.pixels.data()));
        OIIO::ImageBuf rgb =
            tile.channels == 3 ? source : OIIO::ImageBufAlgo::channels(source, 3, {0, 0, 0});
        const int height = std::max(
            1, static_cast<int>(std::lround(double(tile.height) * tileWidth / tile.width)));
        OIIO::ImageBuf resized =
            OIIO::ImageBufAlgo::resize(rgb, "", 0, OIIO::ROI(0, tileWidth, 0, height, 0, 1, 0, 3));
        const float yellow[3] = {1.0f, 1.0f, 0.3f};
        OIIO::ImageBufAlgo::render_text(resized, 5, 16, tile.label, 14, kFont, yellow);
        rowHeight = std::max(rowHeight, height);
        scaled.push_back(std::move(resized));
    }
    const int rows = static_cast<int>((tiles.size() + static_cast<std::size_t>(columns) - 1) /
                                      static_cast<std::size_t>(columns));
    const int usedColumns = std::min<int>(columns, static_cast<int>(tiles.size()));
    OIIO::ImageBuf sheet(OIIO::ImageSpec(usedColumns * (tileWidth + kPad) + kPad,
                                         rows * (rowHeight + kPad) + kPad, 3,
                                         OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::zero(sheet);
    for (std::size_t i = 0; i < scaled.size(); ++i) {
        const int column = static_cast<int>(i % static_cast<std::size_t>(columns));
        const int row = static_cast<int>(i / static_cast<std::size_t>(columns));
        OIIO::ImageBufAlgo::paste(sheet, kPad + column * (tileWidth + kPad),
                                  kPad + row * (rowHeight + kPad), 0, 0, scaled[i]);
    }
    proto::AtomicFile output(path);
    if (!sheet.write(output.temporaryPath().string(), OIIO::TypeDesc::UINT8)) {
        throw common::InputError(path, "cannot write the contact sheet: " + sheet.geterror());
    }
    output.commit();
}

SheetTile scalarTile(std::string label, int width, int height, const std::vector<float>& values,
                     float low, float high) {
    // A few stops of a viridis-like ramp, interpolated linearly.
    static constexpr std::array<std::array<float, 3>, 5> kRamp{{{0.27f, 0.00f, 0.33f},
                                                                {0.23f, 0.32f, 0.55f},
                                                                {0.13f, 0.57f, 0.55f},
                                                                {0.37f, 0.79f, 0.38f},
                                                                {0.99f, 0.91f, 0.14f}}};
    SheetTile tile;
    tile.label = std::move(label);
    tile.width = width;
    tile.height = height;
    tile.channels = 3;
    tile.pixels.assign(values.size() * 3, 0.0f);
    const float span = high > low ? high - low : 1.0f;
    for (std::size_t p = 0; p < values.size(); ++p) {
        if (std::isnan(values[p])) {
            continue;
        }
        const float t = std::clamp((values[p] - low) / span, 0.0f, 1.0f) * (kRamp.size() - 1);
        const auto k = std::min(static_cast<std::size_t>(t), kRamp.size() - 2);
        const float f = t - static_cast<float>(k);
        for (std::size_t c = 0; c < 3; ++c) {
            tile.pixels[3 * p + c] = kRamp[k][c] + f * (kRamp[k + 1][c] - kRamp[k][c]);
        }
    }
    return tile;
}

}  // namespace vpe::image
