// SPDX-License-Identifier: MIT
// TileCover: the covered tiles as quads (see the header).
#include "tile_cover.h"

#include <algorithm>

#include <GLES3/gl31.h>

namespace vpe::renderer::gles {

TileCover::TileCover(int width, int height, const std::vector<std::uint8_t>& covered) {
    const int tilesX = (width + kTileSize - 1) / kTileSize;
    const int tilesY = (height + kTileSize - 1) / kTileSize;
    std::vector<float> corners;
    const auto isCovered = [&](int tx, int ty) {
        return covered[static_cast<std::size_t>(ty * tilesX + tx)] != 0;
    };
    for (int ty = 0; ty < tilesY; ++ty) {
        for (int tx = 0; tx < tilesX; ++tx) {
            if (!isCovered(tx, ty)) {
                continue;
            }
            int end = tx + 1;
            while (end < tilesX && isCovered(end, ty)) {
                ++end;
            }
            const auto x0 = static_cast<float>(tx * kTileSize);
            const auto y0 = static_cast<float>(ty * kTileSize);
            const auto x1 = static_cast<float>(std::min(width, end * kTileSize));
            const auto y1 = static_cast<float>(std::min(height, (ty + 1) * kTileSize));
            corners.insert(corners.end(), {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1});
            ++quads_;
            tx = end;
        }
    }
    // Tiles covered / all tiles above which the whole screen is drawn.
    constexpr double kFullScreenAbove = 0.5;
    std::size_t coveredTiles = 0;
    for (const std::uint8_t flag : covered) {
        coveredTiles += flag != 0 ? 1 : 0;
    }
    fullScreen_ =
        static_cast<double>(coveredTiles) > kFullScreenAbove * static_cast<double>(tilesX * tilesY);
    if (fullScreen_) {  // one triangle over [0, W] × [0, H]
        const auto w = static_cast<float>(width), h = static_cast<float>(height);
        corners = {0.0f, 0.0f, 2.0f * w, 0.0f, 0.0f, 2.0f * h};
    }
    buffer_ = GlObject::buffer();
    vertexArray_ = GlObject::vertexArray();
    glBindVertexArray(vertexArray_.get());
    glBindBuffer(GL_ARRAY_BUFFER, buffer_.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(corners.size() * sizeof(float)),
                 corners.empty() ? nullptr : corners.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    checkGlError("uploading the projector's tile cover");
}

void TileCover::draw() const {
    if (quads_ == 0) {
        return;
    }
    glBindVertexArray(vertexArray_.get());
    glDrawArrays(GL_TRIANGLES, 0, fullScreen_ ? 3 : static_cast<GLsizei>(6 * quads_));
    glBindVertexArray(0);
}

std::string tileVertexSource() {
    return R"GLSL(#version 310 es
layout(location = 0) in vec2 aCorner;  // projector pixels, rows from the top
uniform bool uTopRowAtOrigin;
uniform vec2 uSize;
void main() {
    vec2 window = vec2(aCorner.x, uTopRowAtOrigin ? aCorner.y : uSize.y - aCorner.y);
    gl_Position = vec4(window / uSize * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";
}

}  // namespace vpe::renderer::gles
