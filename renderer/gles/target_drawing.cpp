// SPDX-License-Identifier: MIT
// A black frame, and an RGBA8 image uploaded and blitted into a target.
#include "vpe/renderer/gles/target_drawing.h"

#include <cstdio>
#include <string>

#include <GLES3/gl31.h>

namespace vpe::renderer::gles {

namespace {

std::string sizeName(int width, int height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void checkGl(const char* what) {
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", error);
        throw GraphicsError(std::string(what) + " failed (GL error " + code + ")");
    }
}

}  // namespace

void clearToBlack(RenderTarget& target) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    glViewport(0, 0, target.width(), target.height());
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
}

ImageBlitter::ImageBlitter(int width, int height) : width_(width), height_(height) {
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    const GLenum status = glCheckFramebufferStatus(GL_READ_FRAMEBUFFER);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    try {
        checkGl(("creating the " + sizeName(width, height) + " image texture").c_str());
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            throw GraphicsError("the " + sizeName(width, height) +
                                " image framebuffer is incomplete");
        }
    } catch (...) {
        glDeleteFramebuffers(1, &framebuffer_);
        glDeleteTextures(1, &texture_);
        throw;
    }
}

ImageBlitter::~ImageBlitter() {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteTextures(1, &texture_);
}

void ImageBlitter::draw(RenderTarget& target, std::span<const std::uint8_t> rgba) {
    const std::size_t bytes =
        static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 4;
    if (rgba.size() != bytes || target.width() != width_ || target.height() != height_) {
        throw GraphicsError("an image of " + std::to_string(rgba.size()) + " bytes for a " +
                            sizeName(width_, height_) + " blitter into a " +
                            sizeName(target.width(), target.height()) + " target");
    }
    // Texture row 0 is the image's top row; the target's GL origin is its top row (an FBO read
    // back top-first) or its bottom row (a scanout surface): the blit flips in the latter case.
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE,
                    rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer());
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const bool top = target.topRowAtGlOrigin();
    glBlitFramebuffer(0, 0, width_, height_, 0, top ? 0 : height_, width_, top ? height_ : 0,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    checkGl("blitting an image");
}

}  // namespace vpe::renderer::gles
