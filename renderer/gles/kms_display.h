// SPDX-License-Identifier: MIT
// KmsDisplay (private to renderer/gles): the DRM half of KmsPlatform, kmscube's drm-common +
// drm-legacy (atomic through KmsAtomic, kms_atomic.h) — the device, connector, mode and CRTC,
// framebuffers for GBM buffers, the first modeset and page flips that wait for vsync.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <xf86drmMode.h>

#include "kms_atomic.h"

namespace vpe::renderer::gles {

struct KmsOptions;

class KmsDisplay {
public:
    // Opens the node and chooses connector, mode and CRTC. Throws GraphicsError.
    explicit KmsDisplay(const KmsOptions& options);
    ~KmsDisplay();
    KmsDisplay(const KmsDisplay&) = delete;
    KmsDisplay& operator=(const KmsDisplay&) = delete;

    int fd() const { return fd_; }
    const std::string& device() const { return device_; }
    const std::string& connectorName() const { return connectorName_; }
    const drmModeModeInfo& mode() const { return mode_; }
    int width() const { return mode_.hdisplay; }
    int height() const { return mode_.vdisplay; }

    // "atomic" or "legacy": what show() uses (atomic when the device has it and the first
    // atomic commit succeeded; legacy otherwise).
    const char* modesetting() const { return atomic_ ? "atomic" : "legacy"; }

    // Shows framebuffer `fb`: the first time a modeset (an atomic commit with ALLOW_MODESET,
    // or drmModeSetCrtc; synchronous, flipPending() stays false), then page flips (an atomic
    // NONBLOCK commit or drmModePageFlip) with DRM_MODE_PAGE_FLIP_EVENT, returning at once with
    // flipPending() true. A flip still pending is waited for first. Throws GraphicsError.
    void show(std::uint32_t fb);
    bool flipPending() const { return flipPending_; }
    // Reads the DRM events that are there (fd() is readable); clears flipPending() when the
    // flip has happened.
    void handleEvents();
    // Blocks until the pending flip has happened (at most 1 s: then GraphicsError).
    void waitForFlip();

private:
    void open(const std::string& device);
    void choose(const KmsOptions& options);

    int fd_ = -1;
    std::string device_;
    std::string connectorName_;
    std::uint32_t connectorId_ = 0, crtcId_ = 0;
    int crtcIndex_ = -1;
    std::unique_ptr<KmsAtomic> atomic_;  // null: legacy modesetting
    drmModeModeInfo mode_{};
    drmModeCrtc* savedCrtc_ = nullptr;  // owned: restored and freed on destruction
    bool modeSet_ = false;
    bool flipPending_ = false;  // cleared by the page-flip event handler
};

}  // namespace vpe::renderer::gles
