// SPDX-License-Identifier: MIT
// KmsAtomic (private to renderer/gles): atomic modesetting for KmsDisplay, kmscube's
// drm-atomic — the CRTC's primary plane, the property ids by name, a mode blob; the first
// commit sets the mode (ALLOW_MODESET), later ones flip (NONBLOCK | PAGE_FLIP_EVENT).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <xf86drmMode.h>

namespace vpe::renderer::gles {

class KmsAtomic {
public:
    // nullptr, with `why` set, when the device has no atomic modesetting for this CRTC (no
    // DRM_CLIENT_CAP_ATOMIC, no primary plane, a property missing): the caller uses legacy.
    static std::unique_ptr<KmsAtomic> create(int fd, std::uint32_t crtcId, int crtcIndex,
                                             std::uint32_t connectorId, const drmModeModeInfo& mode,
                                             std::string& why);
    ~KmsAtomic();
    KmsAtomic(const KmsAtomic&) = delete;
    KmsAtomic& operator=(const KmsAtomic&) = delete;

    // Commits `fb` on the primary plane: blocking with ALLOW_MODESET when `modeset`, else
    // non-blocking with a page flip event whose user data is `event`. Returns 0 or -errno.
    int commit(std::uint32_t fb, bool modeset, void* event);

private:
    KmsAtomic() = default;
    struct Ids {
        std::uint32_t connectorCrtcId = 0;
        std::uint32_t crtcModeId = 0, crtcActive = 0;
        std::uint32_t planeFbId = 0, planeCrtcId = 0;
        std::uint32_t srcX = 0, srcY = 0, srcW = 0, srcH = 0;
        std::uint32_t crtcX = 0, crtcY = 0, crtcW = 0, crtcH = 0;
    };
    int fd_ = -1;
    std::uint32_t crtcId_ = 0, connectorId_ = 0, planeId_ = 0, modeBlob_ = 0;
    std::uint32_t width_ = 0, height_ = 0;
    Ids ids_;
};

}  // namespace vpe::renderer::gles
