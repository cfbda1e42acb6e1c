// SPDX-License-Identifier: MIT
// KmsDisplay: DRM device, connector, mode and CRTC selection; legacy modeset and page flips.
#include "kms_display.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>
#include <xf86drm.h>

#include "vpe/renderer/gles/kms_platform.h"

namespace vpe::renderer::gles {

namespace {

struct ResourcesDeleter {
    void operator()(drmModeRes* r) const { drmModeFreeResources(r); }
};
struct ConnectorDeleter {
    void operator()(drmModeConnector* c) const { drmModeFreeConnector(c); }
};
struct EncoderDeleter {
    void operator()(drmModeEncoder* e) const { drmModeFreeEncoder(e); }
};
using Resources = std::unique_ptr<drmModeRes, ResourcesDeleter>;
using Connector = std::unique_ptr<drmModeConnector, ConnectorDeleter>;
using Encoder = std::unique_ptr<drmModeEncoder, EncoderDeleter>;

std::string nameOf(const drmModeConnector& connector) {
    const char* type = drmModeGetConnectorTypeName(connector.connector_type);
    return std::string(type != nullptr ? type : "Unknown") + "-" +
           std::to_string(connector.connector_type_id);
}

std::string modeName(const drmModeModeInfo& mode) {
    return std::to_string(mode.hdisplay) + "x" + std::to_string(mode.vdisplay) + "@" +
           std::to_string(mode.vrefresh);
}

// kmscube's find_crtc_for_encoder / find_crtc_for_connector: the encoder's current CRTC, else
// the first CRTC any of the connector's encoders can drive. 0 when none.
std::uint32_t findCrtc(int fd, const drmModeRes& resources, const drmModeConnector& connector) {
    if (connector.encoder_id != 0) {
        const Encoder encoder(drmModeGetEncoder(fd, connector.encoder_id));
        if (encoder && encoder->crtc_id != 0) {
            return encoder->crtc_id;
        }
    }
    for (int e = 0; e < connector.count_encoders; ++e) {
        const Encoder encoder(drmModeGetEncoder(fd, connector.encoders[e]));
        if (!encoder) {
            continue;
        }
        for (int c = 0; c < resources.count_crtcs; ++c) {
            if ((encoder->possible_crtcs & (1u << static_cast<unsigned>(c))) != 0) {
                return resources.crtcs[c];
            }
        }
    }
    return 0;
}

void pageFlipHandler(int, unsigned, unsigned, unsigned, void* data) {
    *static_cast<bool*>(data) = false;
}

}  // namespace

KmsDisplay::KmsDisplay(const KmsOptions& options) {
    if (options.device == "auto") {
        for (int n = 0; n < 8 && fd_ < 0; ++n) {
            const std::string node = "/dev/dri/card" + std::to_string(n);
            if (!std::filesystem::exists(node)) {
                continue;
            }
            try {
                open(node);
                choose(options);
            } catch (const GraphicsError&) {
                if (fd_ >= 0) {
                    ::close(fd_);
                    fd_ = -1;
                }
            }
        }
        if (fd_ < 0) {
            throw GraphicsError(
                "/dev/dri: no KMS device with a usable connector (KMS display "
                "unavailable)");
        }
        return;
    }
    open(options.device);
    try {
        choose(options);
    } catch (...) {
        ::close(fd_);
        fd_ = -1;
        throw;
    }
}

KmsDisplay::~KmsDisplay() {
    atomic_.reset();
    if (savedCrtc_ != nullptr) {
        if (modeSet_) {
            drmModeSetCrtc(fd_, savedCrtc_->crtc_id, savedCrtc_->buffer_id, savedCrtc_->x,
                           savedCrtc_->y, &connectorId_, 1, &savedCrtc_->mode);
        }
        drmModeFreeCrtc(savedCrtc_);
    }
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void KmsDisplay::open(const std::string& device) {
    device_ = device;
    fd_ = ::open(device.c_str(), O_RDWR | O_CLOEXEC);
    if (fd_ < 0) {
        const int error = errno;
        if (error == ENOENT || error == ENODEV || error == ENXIO) {
            throw GraphicsError(device + ": no such device (KMS display unavailable)");
        }
        throw GraphicsError(device + ": cannot open (" + std::strerror(error) +
                            ") (KMS display unavailable)");
    }
}

void KmsDisplay::choose(const KmsOptions& options) {
    const Resources resources(drmModeGetResources(fd_));
    if (!resources) {
        throw GraphicsError(
            device_ + ": not a KMS device (drmModeGetResources: " + std::strerror(errno) + ")");
    }
    Connector chosen;
    std::string connected;
    for (int i = 0; i < resources->count_connectors && !chosen; ++i) {
        Connector connector(drmModeGetConnector(fd_, resources->connectors[i]));
        if (!connector) {
            continue;
        }
        const std::string name = nameOf(*connector);
        const bool usable =
            connector->connection == DRM_MODE_CONNECTED && connector->count_modes > 0;
        if (usable) {
            connected += (connected.empty() ? "" : ", ") + name;
        }
        if (usable && (options.connector == "auto" || options.connector == name)) {
            chosen = std::move(connector);
        } else if (!usable && options.connector == name) {
            throw GraphicsError(device_ + ": connector " + name + " is not connected (connected: " +
                                (connected.empty() ? "none so far" : connected) + ")");
        }
    }
    if (!chosen) {
        throw GraphicsError(device_ + ": " +
                            (options.connector == "auto"
                                 ? std::string("no connected connector")
                                 : "no connector " + options.connector + " (connected: " +
                                       (connected.empty() ? "none" : connected) + ")") +
                            " (KMS display unavailable)");
    }
    connectorName_ = nameOf(*chosen);

    // The mode: the board's, else the preferred one, else the largest (kmscube).
    const drmModeModeInfo* mode = nullptr;
    std::string modes;
    int largest = -1;
    for (int i = 0; i < chosen->count_modes; ++i) {
        const drmModeModeInfo& m = chosen->modes[i];
        modes += (modes.empty() ? "" : ", ") + modeName(m);
        if (options.modeWidth > 0) {
            if (mode == nullptr && m.hdisplay == options.modeWidth &&
                m.vdisplay == options.modeHeight &&
                (options.modeRefresh == 0 || static_cast<int>(m.vrefresh) == options.modeRefresh)) {
                mode = &m;
            }
        } else if ((m.type & DRM_MODE_TYPE_PREFERRED) != 0) {
            mode = &m;
            largest = 1 << 30;
        } else if (m.hdisplay * m.vdisplay > largest) {
            mode = &m;
            largest = m.hdisplay * m.vdisplay;
        }
    }
    if (mode == nullptr) {
        throw GraphicsError(
            device_ + ": no mode " + std::to_string(options.modeWidth) + "x" +
            std::to_string(options.modeHeight) +
            (options.modeRefresh > 0 ? "@" + std::to_string(options.modeRefresh) : std::string()) +
            " on " + connectorName_ + " (modes: " + modes + ")");
    }
    mode_ = *mode;
    connectorId_ = chosen->connector_id;
    crtcId_ = findCrtc(fd_, *resources, *chosen);
    if (crtcId_ == 0) {
        throw GraphicsError(device_ + ": no CRTC can drive connector " + connectorName_);
    }
    for (int c = 0; c < resources->count_crtcs; ++c) {
        if (resources->crtcs[c] == crtcId_) {
            crtcIndex_ = c;
        }
    }
    savedCrtc_ = drmModeGetCrtc(fd_, crtcId_);
    if (options.atomic && crtcIndex_ >= 0) {
        std::string why;  // without atomic modesetting: legacy, as the caller allowed
        atomic_ = KmsAtomic::create(fd_, crtcId_, crtcIndex_, connectorId_, mode_, why);
    }
}

void KmsDisplay::show(std::uint32_t fb) {
    if (!modeSet_) {
        // Atomic first; a device that refuses the atomic modeset falls back to legacy.
        if (atomic_ && atomic_->commit(fb, true, nullptr) != 0) {
            atomic_.reset();
        }
        if (!atomic_ && drmModeSetCrtc(fd_, crtcId_, fb, 0, 0, &connectorId_, 1, &mode_) != 0) {
            throw GraphicsError(device_ + ": drmModeSetCrtc " + modeName(mode_) + " on " +
                                connectorName_ + " failed: " + std::strerror(errno));
        }
        modeSet_ = true;
        return;
    }
    waitForFlip();  // one flip in flight at a time
    flipPending_ = true;
    if (atomic_) {
        const int error = atomic_->commit(fb, false, &flipPending_);
        if (error != 0) {
            flipPending_ = false;
            if (error == -ENODEV) {
                throw DisplayLostError(device_ + ": the display went away (atomic page flip: " +
                                       std::strerror(-error) + ")");
            }
            throw GraphicsError(device_ + ": atomic page flip failed: " + std::strerror(-error));
        }
    } else if (drmModePageFlip(fd_, crtcId_, fb, DRM_MODE_PAGE_FLIP_EVENT, &flipPending_) != 0) {
        const int error = errno;
        flipPending_ = false;
        if (error == ENODEV) {
            throw DisplayLostError(device_ + ": the display went away (drmModePageFlip: " +
                                   std::strerror(error) + ")");
        }
        throw GraphicsError(device_ + ": drmModePageFlip failed: " + std::strerror(error));
    }
}

void KmsDisplay::handleEvents() {
    drmEventContext events{};
    events.version = 2;
    events.page_flip_handler = pageFlipHandler;
    drmHandleEvent(fd_, &events);
}

void KmsDisplay::waitForFlip() {
    while (flipPending_) {
        pollfd descriptor{fd_, POLLIN, 0};
        const int ready = ::poll(&descriptor, 1, 1000);
        if (ready < 0 && errno == EINTR) {
            continue;
        }
        if (ready <= 0) {
            flipPending_ = false;
            throw GraphicsError(device_ + ": no page flip event within 1 s" +
                                (ready < 0 ? std::string(": ") + std::strerror(errno) : ""));
        }
        handleEvents();
    }
}

}  // namespace vpe::renderer::gles
