// SPDX-License-Identifier: MIT
// KmsPlatform: OpenGL ES 3.1 on a DRM/KMS display through GBM and EGL (EGL_KHR_platform_gbm),
// in kmscube's call order: open the DRM node, drmModeGetResources, pick the connector and the
// mode, find an encoder and CRTC, gbm_create_device, gbm_surface_create, EGL on that surface.
// Its one RenderTarget is the scanout surface; present() swaps, adds the front buffer as a
// framebuffer, sets the mode on the first frame and page-flips afterwards, waiting for the
// flip event (vsync): atomic modesetting (kmscube's drm-atomic: primary plane, mode blob,
// ALLOW_MODESET then NONBLOCK | PAGE_FLIP_EVENT commits) with a legacy fallback
// (drmModeSetCrtc / drmModePageFlip, kmscube's drm-legacy). Filament's PlatformEGL next to
// HeadlessEglPlatform. Never run on real hardware yet: it compiles, and its absence is tested.
#pragma once

#include <memory>
#include <string>

#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

struct KmsOptions {
    // The DRM node ("/dev/dri/card0"), or "auto": the first /dev/dri/card* with a connector.
    std::string device = "/dev/dri/card0";
    // A connector name as the kernel spells it ("HDMI-A-1", "DSI-1"), or "auto": the first
    // connected one.
    std::string connector = "auto";
    // The mode: 0 × 0 = the connector's preferred mode; refresh 0 = any rate of that size.
    int modeWidth = 0, modeHeight = 0, modeRefresh = 0;
    // Atomic modesetting when the device has it (DRM_CLIENT_CAP_ATOMIC, a primary plane) and
    // its first commit succeeds; legacy (drmModeSetCrtc / drmModePageFlip) otherwise or when
    // false.
    bool atomic = true;
    int majorVersion = 3, minorVersion = 1;
};

// Throws GraphicsError with one line: "/dev/dri/card0: no such device (KMS display
// unavailable)", "/dev/dri/card1: not a KMS device (drmModeGetResources: …)", "/dev/dri/card1:
// connector HDMI-A-2 is not connected (connected: HDMI-A-1)", "…: no mode 1280x720@50 on
// HDMI-A-1 (modes: …)", "EGL: client extension EGL_KHR_platform_gbm is missing", …
std::unique_ptr<GraphicsPlatform> createKmsPlatform(const KmsOptions& options = {});

}  // namespace vpe::renderer::gles
