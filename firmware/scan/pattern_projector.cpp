// SPDX-License-Identifier: MIT
// PatternProjector: upload (grey or RGB), blit, present, and on KMS wait for the flip.
#include "vpe/firmware/scan/pattern_projector.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>

#include <GLES3/gl3.h>
#include <poll.h>

namespace vpe::firmware {

namespace gles = renderer::gles;

namespace {

constexpr int kFlipTimeoutMs = 1000;

std::int64_t monotonicNs() {
    timespec now{};
    ::clock_gettime(CLOCK_MONOTONIC, &now);
    return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

void checkGl(const char* what) {
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", error);
        throw gles::GraphicsError(std::string("scan: ") + what + " failed (GL error " + code + ")");
    }
}

}  // namespace

PatternProjector::PatternProjector(gles::RenderTarget& target) : target_(target) {
    const int width = target.width(), height = target.height();
    rgba_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    const GLenum status = glCheckFramebufferStatus(GL_READ_FRAMEBUFFER);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    checkGl("creating the pattern texture");
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw gles::GraphicsError("scan: the " + std::to_string(width) + "x" +
                                  std::to_string(height) + " pattern framebuffer is incomplete");
    }
}

PatternProjector::~PatternProjector() {
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteTextures(1, &texture_);
}

std::int64_t PatternProjector::show(std::span<const std::uint8_t> codes) {
    const int width = target_.width(), height = target_.height();
    if (codes.size() != rgba_.size() / 4) {
        throw gles::GraphicsError("scan: a pattern of " + std::to_string(codes.size()) +
                                  " pixels for a " + std::to_string(width) + "x" +
                                  std::to_string(height) + " display");
    }
    for (std::size_t i = 0; i < codes.size(); ++i) {
        rgba_[4 * i] = rgba_[4 * i + 1] = rgba_[4 * i + 2] = codes[i];
        rgba_[4 * i + 3] = 255;
    }
    return present();
}

std::int64_t PatternProjector::showRgb(std::span<const std::uint8_t> codes) {
    const int width = target_.width(), height = target_.height();
    if (codes.size() != rgba_.size() / 4 * 3) {
        throw gles::GraphicsError("scan: an RGB image of " + std::to_string(codes.size() / 3) +
                                  " pixels for a " + std::to_string(width) + "x" +
                                  std::to_string(height) + " display");
    }
    for (std::size_t i = 0; 3 * i < codes.size(); ++i) {
        rgba_[4 * i] = codes[3 * i];
        rgba_[4 * i + 1] = codes[3 * i + 1];
        rgba_[4 * i + 2] = codes[3 * i + 2];
        rgba_[4 * i + 3] = 255;
    }
    return present();
}

std::int64_t PatternProjector::present() {
    const int width = target_.width(), height = target_.height();
    // Texture row 0 is the image's top row; the target's GL origin is its top row (an FBO read
    // back top-first) or its bottom row (a scanout surface): the blit flips in the latter case.
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target_.framebuffer());
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const bool top = target_.topRowAtGlOrigin();
    glBlitFramebuffer(0, 0, width, height, 0, top ? 0 : height, width, top ? height : 0,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    checkGl("drawing a pattern");
    target_.present();
    // KMS: present() queued the flip (the first frame's modeset is synchronous); the pattern is
    // on screen once the flip event arrives.
    const int fd = target_.vsyncDescriptor();
    while (fd >= 0 && target_.vsyncPending()) {
        pollfd ready{fd, POLLIN, 0};
        const int result = ::poll(&ready, 1, kFlipTimeoutMs);
        if (result < 0 && errno == EINTR) {
            continue;
        }
        if (result <= 0) {
            throw gles::GraphicsError(result == 0 ? std::string("scan: no page flip within 1 s")
                                                  : std::string("scan: poll on the display (") +
                                                        std::strerror(errno) + ")");
        }
        if (target_.onVsyncReadable()) {
            break;
        }
    }
    return monotonicNs();
}

}  // namespace vpe::firmware
