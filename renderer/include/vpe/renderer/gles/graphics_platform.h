// SPDX-License-Identifier: MIT
// GraphicsPlatform and RenderTarget: the OS and windowing glue behind one interface (Filament's
// Platform split). The renderer draws into a RenderTarget and never knows which platform made
// it: headless EGL (an FBO read back, headless_egl_platform.h) or KMS (GBM scanout buffers with
// page flips, kmscube's call order, kms_platform.h).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vpe::renderer::gles {

// A platform, context or GL failure; what() is one line naming what failed.
class GraphicsError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The display device went away (a projector's connector or the GPU unplugged: ENODEV). Nothing
// more can be drawn on it, and drawing again into its buffers is not safe (Mesa's llvmpipe
// crashed doing so in the KMS test's virtual machine, docs/kms-vm.md): the caller stops.
class DisplayLostError : public GraphicsError {
public:
    using GraphicsError::GraphicsError;
};

// Where a frame goes. The GL context of the platform that made it must be current.
class RenderTarget {
public:
    virtual ~RenderTarget() = default;
    virtual int width() const = 0;
    virtual int height() const = 0;
    // The framebuffer object to draw into (0: the platform's window surface).
    virtual unsigned framebuffer() const = 0;
    // True when GL's window row y = 0 (gl_FragCoord.y = 0.5) is the image's TOP row, as in an
    // FBO read back with glReadPixels into a top-first image; false for a scanout surface,
    // whose GL origin is the bottom-left corner of the screen.
    virtual bool topRowAtGlOrigin() const = 0;
    // Ends a frame: headless waits for the GPU (glFinish); KMS swaps and queues the page flip.
    virtual void present() = 0;
    // Vsync pacing for an event loop. A scanout target's present() queues its page flip and
    // returns; the flip's completion arrives on vsyncDescriptor() (the DRM fd), and
    // onVsyncReadable() handles it, returning true once the frame is on screen (then the next
    // may be presented). A present() while a flip is still queued waits for it first. Headless
    // targets have no descriptor (−1): their present() is done when it returns.
    virtual int vsyncDescriptor() const { return -1; }
    virtual bool onVsyncReadable() { return true; }
    // True while a presented frame waits for its flip (false after a synchronous modeset).
    virtual bool vsyncPending() const { return false; }
    // The frame as RGBA8, rows from the top, width·height·4 bytes. Throws GraphicsError where
    // the target cannot be read (a scanout may not be).
    virtual std::vector<std::uint8_t> readRgba8() const = 0;
};

class GraphicsPlatform {
public:
    virtual ~GraphicsPlatform() = default;
    // "headless EGL (Mesa surfaceless): llvmpipe (LLVM 15.0.6, 256 bits), OpenGL ES 3.1 Mesa …"
    virtual std::string description() const = 0;
    // A target of that size (a KMS platform accepts only its mode's size). Throws GraphicsError
    // for sizes outside 1 … GL_MAX_RENDERBUFFER_SIZE.
    virtual std::unique_ptr<RenderTarget> createRenderTarget(int width, int height) = 0;
    // The one size a target may have when the platform fixes it ({width, height}: a KMS
    // display's mode), for callers that draw whatever the display is (a scan's patterns);
    // empty when any size goes (headless).
    virtual std::optional<std::array<int, 2>> fixedTargetSize() const { return std::nullopt; }
    // Makes the platform's context current on the calling thread.
    virtual void makeCurrent() = 0;
};

}  // namespace vpe::renderer::gles
