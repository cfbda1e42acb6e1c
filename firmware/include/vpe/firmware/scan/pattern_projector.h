// SPDX-License-Identifier: MIT
// PatternProjector: a scan's patterns on the board's display — 8-bit codes copied into the
// renderer's ImageBlitter and blitted full-screen into the render target (no shader, no
// filtering: the projector shows exactly the codes), grey (the structured-light patterns: the same
// level on all three channels) or RGB (the radiometric capture's flat fields), then presented:
// headless, the GPU has finished; KMS, the page flip has completed (the pattern is being scanned
// out).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "vpe/renderer/gles/graphics_platform.h"
#include "vpe/renderer/gles/target_drawing.h"

namespace vpe::firmware {

class PatternProjector {
public:
    // The GL context of the platform that made `target` must be current. Throws
    // renderer::gles::GraphicsError.
    explicit PatternProjector(renderer::gles::RenderTarget& target);
    PatternProjector(const PatternProjector&) = delete;
    PatternProjector& operator=(const PatternProjector&) = delete;

    // Shows width·height codes (rows from the top) and returns once they are displayed (above):
    // the CLOCK_MONOTONIC time then, from which the projector's latency is counted. Throws
    // GraphicsError (a GL error, or no page flip within a second).
    std::int64_t show(std::span<const std::uint8_t> codes);
    // The same with three codes per pixel (R, G, B).
    std::int64_t showRgb(std::span<const std::uint8_t> codes);

    // What the target holds, RGBA8 rows from the top (headless only: a scanout is not read).
    std::vector<std::uint8_t> readBack() const { return target_.readRgba8(); }

private:
    // Blits rgba_ and presents; returns once displayed.
    std::int64_t present();

    renderer::gles::RenderTarget& target_;
    renderer::gles::ImageBlitter blitter_;
    std::vector<std::uint8_t> rgba_;
};

}  // namespace vpe::firmware
