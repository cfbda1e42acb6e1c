// SPDX-License-Identifier: MIT
// KmsPlatform: GBM + EGL on a KmsDisplay (kmscube's common.c order), and the scanout target
// whose present() swaps, locks the front buffer, wraps it in a DRM framebuffer (cached on the
// buffer object) and shows it (modeset, then a queued page flip); the buffer it replaces goes
// back to GBM once the flip event says it is off screen.
#include "vpe/renderer/gles/kms_platform.h"

#include <cstring>
#include <sstream>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl31.h>
#include <gbm.h>
#include <xf86drm.h>

#include "egl_support.h"
#include "kms_display.h"

namespace vpe::renderer::gles {

namespace {

// The DRM framebuffer of a GBM buffer, made once and kept as the buffer's user data
// (kmscube's drm_fb_get_from_bo).
struct BufferFramebuffer {
    int fd;
    std::uint32_t id;
};

void destroyBufferFramebuffer(gbm_bo*, void* data) {
    auto* fb = static_cast<BufferFramebuffer*>(data);
    drmModeRmFB(fb->fd, fb->id);
    delete fb;
}

class KmsPlatform;

class ScanoutTarget final : public RenderTarget {
public:
    explicit ScanoutTarget(KmsPlatform& platform) : platform_(platform) {}
    ~ScanoutTarget() override;
    ScanoutTarget(const ScanoutTarget&) = delete;
    ScanoutTarget& operator=(const ScanoutTarget&) = delete;
    int width() const override;
    int height() const override;
    unsigned framebuffer() const override { return 0; }
    bool topRowAtGlOrigin() const override { return false; }
    void present() override;
    int vsyncDescriptor() const override;
    bool onVsyncReadable() override;
    bool vsyncPending() const override { return queued_ != nullptr; }
    std::vector<std::uint8_t> readRgba8() const override {
        throw GraphicsError("KMS: the scanout surface is not read back (use the headless display)");
    }

private:
    void flipDone();

    KmsPlatform& platform_;       // borrowed: the platform outlives its target
    gbm_bo* previous_ = nullptr;  // on screen
    gbm_bo* queued_ = nullptr;    // flip queued, not yet on screen
};

class KmsPlatform final : public GraphicsPlatform {
public:
    explicit KmsPlatform(const KmsOptions& options) : display_(options) {
        // GBM on the DRM node, a scanout surface of the mode's size (XRGB8888).
        gbm_ = gbm_create_device(display_.fd());
        if (gbm_ == nullptr) {
            throw GraphicsError(display_.device() + ": gbm_create_device failed");
        }
        try {
            surface_ =
                gbm_surface_create(gbm_, static_cast<std::uint32_t>(display_.width()),
                                   static_cast<std::uint32_t>(display_.height()),
                                   GBM_FORMAT_XRGB8888, GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
            if (surface_ == nullptr) {
                throw GraphicsError(display_.device() + ": gbm_surface_create " +
                                    std::to_string(display_.width()) + "x" +
                                    std::to_string(display_.height()) + " XRGB8888 failed");
            }
            createEgl(options);
        } catch (...) {
            release();
            throw;
        }
    }
    ~KmsPlatform() override { release(); }
    KmsPlatform(const KmsPlatform&) = delete;
    KmsPlatform& operator=(const KmsPlatform&) = delete;

    std::string description() const override { return description_; }
    void makeCurrent() override {
        if (eglMakeCurrent(eglDisplay, eglSurface, eglSurface, context_) != EGL_TRUE) {
            throw GraphicsError("EGL: eglMakeCurrent failed: " + eglErrorName(eglGetError()));
        }
    }
    std::optional<std::array<int, 2>> fixedTargetSize() const override {
        return std::array<int, 2>{display_.width(), display_.height()};
    }
    std::unique_ptr<RenderTarget> createRenderTarget(int width, int height) override {
        if (width != display_.width() || height != display_.height()) {
            throw GraphicsError(
                "KMS: render target " + std::to_string(width) + "x" + std::to_string(height) +
                " differs from the mode " + std::to_string(display_.width()) + "x" +
                std::to_string(display_.height()) + " on " + display_.connectorName());
        }
        if (targetMade_) {
            throw GraphicsError("KMS: the scanout surface has one render target");
        }
        targetMade_ = true;
        return std::make_unique<ScanoutTarget>(*this);
    }

    KmsDisplay display_;
    gbm_device* gbm_ = nullptr;
    gbm_surface* surface_ = nullptr;
    EGLDisplay eglDisplay = EGL_NO_DISPLAY;
    EGLSurface eglSurface = EGL_NO_SURFACE;

private:
    void createEgl(const KmsOptions& options) {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        for (const char* name : {"EGL_EXT_platform_base", "EGL_KHR_platform_gbm"}) {
            if (!hasEglExtension(client, name)) {
                throw GraphicsError(std::string("EGL: client extension ") + name + " is missing");
            }
        }
        const auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (getPlatformDisplay == nullptr) {
            throw GraphicsError("EGL: eglGetPlatformDisplayEXT is missing");
        }
        eglDisplay = getPlatformDisplay(EGL_PLATFORM_GBM_KHR, gbm_, nullptr);
        EGLint major = 0, minor = 0;
        if (eglDisplay == EGL_NO_DISPLAY || eglInitialize(eglDisplay, &major, &minor) != EGL_TRUE) {
            eglDisplay = EGL_NO_DISPLAY;
            throw GraphicsError("EGL: no GBM display on " + display_.device() + " (" +
                                eglErrorName(eglGetError()) + ")");
        }
        if (!hasEglExtension(eglQueryString(eglDisplay, EGL_EXTENSIONS),
                             "EGL_KHR_create_context")) {
            throw GraphicsError("EGL: display extension EGL_KHR_create_context is missing");
        }
        if (eglBindAPI(EGL_OPENGL_ES_API) != EGL_TRUE) {
            throw GraphicsError("EGL: OpenGL ES is not supported (eglBindAPI: " +
                                eglErrorName(eglGetError()) + ")");
        }
        // A config whose native visual is the GBM surface's format (kmscube's
        // match_config_to_visual).
        const EGLint configAttributes[] = {EGL_SURFACE_TYPE,
                                           EGL_WINDOW_BIT,
                                           EGL_RED_SIZE,
                                           8,
                                           EGL_GREEN_SIZE,
                                           8,
                                           EGL_BLUE_SIZE,
                                           8,
                                           EGL_RENDERABLE_TYPE,
                                           EGL_OPENGL_ES3_BIT_KHR,
                                           EGL_NONE};
        EGLint count = 0;
        eglChooseConfig(eglDisplay, configAttributes, nullptr, 0, &count);
        std::vector<EGLConfig> configs(static_cast<std::size_t>(count > 0 ? count : 0));
        if (count > 0) {
            eglChooseConfig(eglDisplay, configAttributes, configs.data(), count, &count);
        }
        EGLConfig config = nullptr;
        for (EGLConfig candidate : configs) {
            EGLint visual = 0;
            if (eglGetConfigAttrib(eglDisplay, candidate, EGL_NATIVE_VISUAL_ID, &visual) ==
                    EGL_TRUE &&
                static_cast<std::uint32_t>(visual) == GBM_FORMAT_XRGB8888) {
                config = candidate;
                break;
            }
        }
        if (config == nullptr) {
            throw GraphicsError("EGL: no OpenGL ES 3 window config for XRGB8888 on " +
                                display_.device());
        }
        const std::string version =
            std::to_string(options.majorVersion) + "." + std::to_string(options.minorVersion);
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION_KHR, options.majorVersion,
                                            EGL_CONTEXT_MINOR_VERSION_KHR, options.minorVersion,
                                            EGL_NONE};
        context_ = eglCreateContext(eglDisplay, config, EGL_NO_CONTEXT, contextAttributes);
        if (context_ == EGL_NO_CONTEXT) {
            throw GraphicsError("EGL: cannot create an OpenGL ES " + version +
                                " context: " + eglErrorName(eglGetError()));
        }
        eglSurface = eglCreateWindowSurface(
            eglDisplay, config, reinterpret_cast<EGLNativeWindowType>(surface_), nullptr);
        if (eglSurface == EGL_NO_SURFACE) {
            throw GraphicsError("EGL: cannot create a window surface on the GBM surface: " +
                                eglErrorName(eglGetError()));
        }
        makeCurrent();
        const auto text = [](GLenum name) {
            const auto* value = reinterpret_cast<const char*>(glGetString(name));
            return std::string(value != nullptr ? value : "?");
        };
        description_ = "KMS " + display_.device() + " " + display_.connectorName() + " " +
                       std::to_string(display_.width()) + "x" + std::to_string(display_.height()) +
                       "@" + std::to_string(display_.mode().vrefresh) + " (" +
                       display_.modesetting() + " modesetting): " + text(GL_RENDERER) + ", " +
                       text(GL_VERSION);
    }
    void release() {
        if (eglDisplay != EGL_NO_DISPLAY) {
            eglMakeCurrent(eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            if (eglSurface != EGL_NO_SURFACE) {
                eglDestroySurface(eglDisplay, eglSurface);
            }
            if (context_ != EGL_NO_CONTEXT) {
                eglDestroyContext(eglDisplay, context_);
            }
            eglTerminate(eglDisplay);
        }
        eglDisplay = EGL_NO_DISPLAY;
        eglSurface = EGL_NO_SURFACE;
        context_ = EGL_NO_CONTEXT;
        if (surface_ != nullptr) {
            gbm_surface_destroy(surface_);
            surface_ = nullptr;
        }
        if (gbm_ != nullptr) {
            gbm_device_destroy(gbm_);
            gbm_ = nullptr;
        }
    }

    EGLContext context_ = EGL_NO_CONTEXT;
    std::string description_;
    bool targetMade_ = false;
};

ScanoutTarget::~ScanoutTarget() {
    if (queued_ != nullptr) {
        try {
            platform_.display_.waitForFlip();
        } catch (const GraphicsError&) {
            // The device is going away; the buffers go with the surface.
        }
    }
    for (gbm_bo* bo : {previous_, queued_}) {
        if (bo != nullptr && platform_.surface_ != nullptr) {
            gbm_surface_release_buffer(platform_.surface_, bo);
        }
    }
}

int ScanoutTarget::vsyncDescriptor() const {
    return platform_.display_.fd();
}

bool ScanoutTarget::onVsyncReadable() {
    platform_.display_.handleEvents();
    if (!platform_.display_.flipPending() && queued_ != nullptr) {
        flipDone();
    }
    return !platform_.display_.flipPending();
}

void ScanoutTarget::flipDone() {
    // The queued buffer is on screen: the one it replaced goes back to GBM for rendering.
    if (previous_ != nullptr) {
        gbm_surface_release_buffer(platform_.surface_, previous_);
    }
    previous_ = queued_;
    queued_ = nullptr;
}

int ScanoutTarget::width() const {
    return platform_.display_.width();
}
int ScanoutTarget::height() const {
    return platform_.display_.height();
}

void ScanoutTarget::present() {
    if (queued_ != nullptr) {
        platform_.display_.waitForFlip();  // a caller not pacing by vsyncDescriptor()
        flipDone();
    }
    if (eglSwapBuffers(platform_.eglDisplay, platform_.eglSurface) != EGL_TRUE) {
        throw GraphicsError("EGL: eglSwapBuffers failed: " + eglErrorName(eglGetError()));
    }
    gbm_bo* bo = gbm_surface_lock_front_buffer(platform_.surface_);
    if (bo == nullptr) {
        throw GraphicsError("KMS: gbm_surface_lock_front_buffer failed");
    }
    auto* fb = static_cast<BufferFramebuffer*>(gbm_bo_get_user_data(bo));
    if (fb == nullptr) {
        std::uint32_t id = 0;
        const int fd = platform_.display_.fd();
        if (drmModeAddFB(fd, gbm_bo_get_width(bo), gbm_bo_get_height(bo), 24, 32,
                         gbm_bo_get_stride(bo), gbm_bo_get_handle(bo).u32, &id) != 0) {
            gbm_surface_release_buffer(platform_.surface_, bo);
            throw GraphicsError(platform_.display_.device() +
                                ": drmModeAddFB failed: " + std::strerror(errno));
        }
        fb = new BufferFramebuffer{fd, id};
        gbm_bo_set_user_data(bo, fb, destroyBufferFramebuffer);
    }
    try {
        platform_.display_.show(fb->id);
    } catch (...) {
        gbm_surface_release_buffer(platform_.surface_, bo);
        throw;
    }
    queued_ = bo;
    if (!platform_.display_.flipPending()) {
        flipDone();  // the first frame: a synchronous modeset
    }
}

}  // namespace

std::unique_ptr<GraphicsPlatform> createKmsPlatform(const KmsOptions& options) {
    return std::make_unique<KmsPlatform>(options);
}

}  // namespace vpe::renderer::gles
