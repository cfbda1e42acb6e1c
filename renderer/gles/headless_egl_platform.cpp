// SPDX-License-Identifier: MIT
// HeadlessEglPlatform: EGL surfaceless display, GLES 3.1 context, FBO render targets.
#include "vpe/renderer/gles/headless_egl_platform.h"

#include <cstring>
#include <sstream>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl31.h>

#include "egl_support.h"
#include "gl_program.h"

namespace vpe::renderer::gles {

namespace {

// An FBO with an RGBA8 colour renderbuffer.
class FramebufferTarget final : public RenderTarget {
public:
    FramebufferTarget(int width, int height) : width_(width), height_(height) {
        colour_ = GlObject::renderbuffer();
        glBindRenderbuffer(GL_RENDERBUFFER, colour_.get());
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
        framebuffer_ = GlObject::framebuffer();
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  colour_.get());
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            std::ostringstream out;
            out << "headless EGL: " << width << "x" << height
                << " RGBA8 framebuffer is incomplete (status 0x" << std::hex << status << ")";
            throw GraphicsError(out.str());
        }
        checkGlError("headless EGL: creating the render target");
    }
    int width() const override { return width_; }
    int height() const override { return height_; }
    unsigned framebuffer() const override { return framebuffer_.get(); }
    bool topRowAtGlOrigin() const override { return true; }
    void present() override { glFinish(); }
    std::vector<std::uint8_t> readRgba8() const override {
        std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width_) *
                                         static_cast<std::size_t>(height_) * 4);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        // GL row y = 0 comes first, and it is the image's top row (topRowAtGlOrigin).
        glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        checkGlError("headless EGL: reading the frame back");
        return pixels;
    }

private:
    int width_, height_;
    GlObject colour_, framebuffer_;
};

class HeadlessEglPlatform final : public GraphicsPlatform {
public:
    explicit HeadlessEglPlatform(const HeadlessEglOptions& options) {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        std::vector<std::string> clientNeeded{"EGL_EXT_platform_base",
                                              "EGL_MESA_platform_surfaceless"};
        clientNeeded.insert(clientNeeded.end(), options.extraClientExtensions.begin(),
                            options.extraClientExtensions.end());
        for (const std::string& name : clientNeeded) {
            if (!hasEglExtension(client, name)) {
                throw GraphicsError("EGL: client extension " + name + " is missing");
            }
        }
        const auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (getPlatformDisplay == nullptr) {
            throw GraphicsError("EGL: eglGetPlatformDisplayEXT is missing");
        }
        display_ = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display_ == EGL_NO_DISPLAY) {
            throw GraphicsError("EGL: no surfaceless display (" + eglErrorName(eglGetError()) +
                                ")");
        }
        EGLint major = 0, minor = 0;
        if (eglInitialize(display_, &major, &minor) != EGL_TRUE) {
            const std::string error = eglErrorName(eglGetError());
            display_ = EGL_NO_DISPLAY;  // never initialized: nothing to release
            throw GraphicsError("EGL: no surfaceless display (eglInitialize: " + error + ")");
        }
        try {
            createContext(options);
        } catch (...) {
            release();
            throw;
        }
    }
    ~HeadlessEglPlatform() override { release(); }
    HeadlessEglPlatform(const HeadlessEglPlatform&) = delete;
    HeadlessEglPlatform& operator=(const HeadlessEglPlatform&) = delete;

    std::string description() const override { return description_; }
    void makeCurrent() override {
        if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
            throw GraphicsError("EGL: eglMakeCurrent failed: " + eglErrorName(eglGetError()));
        }
    }
    std::unique_ptr<RenderTarget> createRenderTarget(int width, int height) override {
        GLint maxSize = 0;
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
        if (width < 1 || height < 1 || width > maxSize || height > maxSize) {
            throw GraphicsError("headless EGL: render target " + std::to_string(width) + "x" +
                                std::to_string(height) + " is outside 1 … " +
                                std::to_string(maxSize) + " (GL_MAX_RENDERBUFFER_SIZE)");
        }
        return std::make_unique<FramebufferTarget>(width, height);
    }

private:
    void createContext(const HeadlessEglOptions& options) {
        const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
        std::vector<std::string> needed{"EGL_KHR_surfaceless_context", "EGL_KHR_create_context"};
        needed.insert(needed.end(), options.extraDisplayExtensions.begin(),
                      options.extraDisplayExtensions.end());
        for (const std::string& name : needed) {
            if (!hasEglExtension(extensions, name)) {
                throw GraphicsError("EGL: display extension " + name + " is missing");
            }
        }
        if (eglBindAPI(EGL_OPENGL_ES_API) != EGL_TRUE) {
            throw GraphicsError("EGL: OpenGL ES is not supported (eglBindAPI: " +
                                eglErrorName(eglGetError()) + ")");
        }
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT_KHR,
                                           EGL_SURFACE_TYPE, 0, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (eglChooseConfig(display_, configAttributes, &config, 1, &count) != EGL_TRUE ||
            count < 1) {
            throw GraphicsError("EGL: no OpenGL ES 3 config on the surfaceless display");
        }
        const std::string version =
            std::to_string(options.majorVersion) + "." + std::to_string(options.minorVersion);
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION_KHR, options.majorVersion,
                                            EGL_CONTEXT_MINOR_VERSION_KHR, options.minorVersion,
                                            EGL_NONE};
        context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttributes);
        if (context_ == EGL_NO_CONTEXT) {
            throw GraphicsError("EGL: cannot create an OpenGL ES " + version +
                                " context: " + eglErrorName(eglGetError()));
        }
        makeCurrent();
        GLint major = 0, minor = 0;
        glGetIntegerv(GL_MAJOR_VERSION, &major);
        glGetIntegerv(GL_MINOR_VERSION, &minor);
        if (major * 100 + minor < options.majorVersion * 100 + options.minorVersion) {
            throw GraphicsError("EGL: asked for OpenGL ES " + version + ", got " +
                                std::to_string(major) + "." + std::to_string(minor));
        }
        const auto text = [](GLenum name) {
            const auto* value = reinterpret_cast<const char*>(glGetString(name));
            return std::string(value != nullptr ? value : "?");
        };
        description_ =
            "headless EGL (Mesa surfaceless): " + text(GL_RENDERER) + ", " + text(GL_VERSION);
    }
    // The display is not terminated: EGL hands every caller of the same platform the SAME
    // display, and eglTerminate would invalidate the contexts of every other platform object
    // on it (Mesa 22 has no EGL_KHR_display_reference). It lives until the process ends.
    void release() {
        if (display_ != EGL_NO_DISPLAY) {
            if (eglGetCurrentContext() == context_) {
                eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            }
            if (context_ != EGL_NO_CONTEXT) {
                eglDestroyContext(display_, context_);
            }
        }
        context_ = EGL_NO_CONTEXT;
        display_ = EGL_NO_DISPLAY;
    }

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    std::string description_;
};

}  // namespace

std::unique_ptr<GraphicsPlatform> createHeadlessEglPlatform(const HeadlessEglOptions& options) {
    return std::make_unique<HeadlessEglPlatform>(options);
}

}  // namespace vpe::renderer::gles
