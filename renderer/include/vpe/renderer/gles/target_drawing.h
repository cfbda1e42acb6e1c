// SPDX-License-Identifier: MIT
// Drawing into a RenderTarget without a bundle: a blank (black) frame, and a CPU image copied
// 1:1 onto the target (a scan's patterns). The callers (the player's blackout, the scan's
// pattern projector) stay free of GL: the renderer owns every GL call.
#pragma once

#include <cstdint>
#include <span>

#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

// Clears the whole target (no scissor) to opaque black. Does not present. The GL context of
// the platform that made `target` must be current.
void clearToBlack(RenderTarget& target);

// A width×height RGBA8 image held in a texture and blitted full-screen into a target of the
// same size: no shader, no filtering, so the target holds exactly the image's codes, rows from
// the top whichever way the target's GL origin lies (RenderTarget::topRowAtGlOrigin).
class ImageBlitter {
public:
    // The GL context that draws must be current (for the blitter's life). Throws
    // GraphicsError naming the size where the texture or its framebuffer cannot be made.
    ImageBlitter(int width, int height);
    ~ImageBlitter();
    ImageBlitter(const ImageBlitter&) = delete;
    ImageBlitter& operator=(const ImageBlitter&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }

    // Uploads `rgba` (width·height·4 bytes, rows from the top) and copies it into `target`
    // (of the blitter's size). Does not present. Throws GraphicsError for a size that does not
    // match, or a GL error.
    void draw(RenderTarget& target, std::span<const std::uint8_t> rgba);

private:
    int width_ = 0, height_ = 0;
    unsigned texture_ = 0;
    unsigned framebuffer_ = 0;
};

}  // namespace vpe::renderer::gles
