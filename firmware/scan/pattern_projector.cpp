// SPDX-License-Identifier: MIT
// PatternProjector: codes to RGBA (grey or RGB), the renderer's blit, present, and on KMS wait
// for the flip.
#include "vpe/firmware/scan/pattern_projector.h"

#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>

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

// The renderer's message, said to be the scan's.
[[noreturn]] void rethrowForScan(const gles::GraphicsError& error) {
    throw gles::GraphicsError(std::string("scan: ") + error.what());
}

gles::ImageBlitter makeBlitter(const gles::RenderTarget& target) {
    try {
        return gles::ImageBlitter(target.width(), target.height());
    } catch (const gles::GraphicsError& error) {
        rethrowForScan(error);
    }
}

}  // namespace

PatternProjector::PatternProjector(gles::RenderTarget& target)
    : target_(target), blitter_(makeBlitter(target)) {
    rgba_.resize(static_cast<std::size_t>(target.width()) *
                 static_cast<std::size_t>(target.height()) * 4);
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
    try {
        blitter_.draw(target_, rgba_);
    } catch (const gles::GraphicsError& error) {
        rethrowForScan(error);
    }
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
