// SPDX-License-Identifier: MIT
// TileCover: the projector's 64 × 64 pixel tiles that contain a pixel seeing the object, each
// row's runs of neighbouring tiles merged into one quad, as a vertex buffer. The frame and the
// material pass draw these instead of a full-screen triangle, so pixels that can only ever be
// black (the object covers a tenth of the demo's frame) run no shader at all; the target is
// cleared to black first. 64: llvmpipe bins fragments in 64 × 64 tiles and shades fully covered
// ones fastest (16-pixel quads made the fully covered benchmark frame 60% slower); runs keep
// the quads few for a tile-based GPU's binning too. When most tiles are covered anyway, one
// full-screen triangle is drawn instead: a quad's diagonal splits every bin it crosses between
// two triangles, which cost llvmpipe 25% on a frame 80% covered.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gl_program.h"

namespace vpe::renderer::gles {

inline constexpr int kTileSize = 64;

class TileCover {
public:
    // `covered`: one flag per tile, row-major, tiles of kTileSize pixels (the last row and
    // column cut to the image). A GL ES 3.1 context must be current.
    TileCover(int width, int height, const std::vector<std::uint8_t>& covered);

    // Draws the quads with the bound program, whose vertex stage is tileVertexSource().
    void draw() const;
    std::size_t quads() const { return quads_; }
    // Drawing one full-screen triangle rather than the quads.
    bool fullScreen() const { return fullScreen_; }

private:
    std::size_t quads_ = 0;
    bool fullScreen_ = false;
    GlObject buffer_, vertexArray_;
};

// The vertex shader drawing TileCover's quads: attribute 0 a corner in projector pixels (edges,
// rows from the top); uniforms uTopRowAtOrigin (bool) and uSize (vec2).
std::string tileVertexSource();

}  // namespace vpe::renderer::gles
