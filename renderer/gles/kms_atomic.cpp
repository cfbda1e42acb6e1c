// SPDX-License-Identifier: MIT
// KmsAtomic: primary plane, property ids, mode blob, atomic commits (kmscube's drm-atomic.c).
#include "kms_atomic.h"

#include <cerrno>

#include <xf86drm.h>

namespace vpe::renderer::gles {

namespace {

// The id of the property called `name` on the object, 0 when it has none.
std::uint32_t propertyId(int fd, std::uint32_t object, std::uint32_t type, const char* name) {
    drmModeObjectProperties* properties = drmModeObjectGetProperties(fd, object, type);
    if (properties == nullptr) {
        return 0;
    }
    std::uint32_t id = 0;
    for (std::uint32_t i = 0; i < properties->count_props && id == 0; ++i) {
        drmModePropertyRes* property = drmModeGetProperty(fd, properties->props[i]);
        if (property != nullptr) {
            if (std::string(property->name) == name) {
                id = property->prop_id;
            }
            drmModeFreeProperty(property);
        }
    }
    drmModeFreeObjectProperties(properties);
    return id;
}

// The value of property `name` on the object (found: true).
bool propertyValue(int fd, std::uint32_t object, std::uint32_t type, const char* name,
                   std::uint64_t& value) {
    drmModeObjectProperties* properties = drmModeObjectGetProperties(fd, object, type);
    if (properties == nullptr) {
        return false;
    }
    bool found = false;
    for (std::uint32_t i = 0; i < properties->count_props && !found; ++i) {
        drmModePropertyRes* property = drmModeGetProperty(fd, properties->props[i]);
        if (property != nullptr) {
            if (std::string(property->name) == name) {
                value = properties->prop_values[i];
                found = true;
            }
            drmModeFreeProperty(property);
        }
    }
    drmModeFreeObjectProperties(properties);
    return found;
}

}  // namespace

std::unique_ptr<KmsAtomic> KmsAtomic::create(int fd, std::uint32_t crtcId, int crtcIndex,
                                             std::uint32_t connectorId, const drmModeModeInfo& mode,
                                             std::string& why) {
    if (drmSetClientCap(fd, DRM_CLIENT_CAP_UNIVERSAL_PLANES, 1) != 0 ||
        drmSetClientCap(fd, DRM_CLIENT_CAP_ATOMIC, 1) != 0) {
        why = "no atomic modesetting (DRM_CLIENT_CAP_ATOMIC)";
        return nullptr;
    }
    std::unique_ptr<KmsAtomic> atomic(new KmsAtomic());
    atomic->fd_ = fd;
    atomic->crtcId_ = crtcId;
    atomic->connectorId_ = connectorId;
    atomic->width_ = mode.hdisplay;
    atomic->height_ = mode.vdisplay;
    // The CRTC's primary plane (kmscube's get_plane_id).
    drmModePlaneRes* planes = drmModeGetPlaneResources(fd);
    if (planes != nullptr) {
        for (std::uint32_t i = 0; i < planes->count_planes && atomic->planeId_ == 0; ++i) {
            drmModePlane* plane = drmModeGetPlane(fd, planes->planes[i]);
            if (plane == nullptr) {
                continue;
            }
            std::uint64_t type = 0;
            if ((plane->possible_crtcs & (1u << static_cast<unsigned>(crtcIndex))) != 0 &&
                propertyValue(fd, plane->plane_id, DRM_MODE_OBJECT_PLANE, "type", type) &&
                type == DRM_PLANE_TYPE_PRIMARY) {
                atomic->planeId_ = plane->plane_id;
            }
            drmModeFreePlane(plane);
        }
        drmModeFreePlaneResources(planes);
    }
    if (atomic->planeId_ == 0) {
        why = "no primary plane for the CRTC";
        return nullptr;
    }
    Ids& ids = atomic->ids_;
    const auto plane = [&](const char* name) {
        return propertyId(fd, atomic->planeId_, DRM_MODE_OBJECT_PLANE, name);
    };
    ids.connectorCrtcId = propertyId(fd, connectorId, DRM_MODE_OBJECT_CONNECTOR, "CRTC_ID");
    ids.crtcModeId = propertyId(fd, crtcId, DRM_MODE_OBJECT_CRTC, "MODE_ID");
    ids.crtcActive = propertyId(fd, crtcId, DRM_MODE_OBJECT_CRTC, "ACTIVE");
    ids.planeFbId = plane("FB_ID");
    ids.planeCrtcId = plane("CRTC_ID");
    ids.srcX = plane("SRC_X");
    ids.srcY = plane("SRC_Y");
    ids.srcW = plane("SRC_W");
    ids.srcH = plane("SRC_H");
    ids.crtcX = plane("CRTC_X");
    ids.crtcY = plane("CRTC_Y");
    ids.crtcW = plane("CRTC_W");
    ids.crtcH = plane("CRTC_H");
    for (const std::uint32_t id :
         {ids.connectorCrtcId, ids.crtcModeId, ids.crtcActive, ids.planeFbId, ids.planeCrtcId,
          ids.srcX, ids.srcY, ids.srcW, ids.srcH, ids.crtcX, ids.crtcY, ids.crtcW, ids.crtcH}) {
        if (id == 0) {
            why = "a connector, CRTC or plane property is missing";
            return nullptr;
        }
    }
    if (drmModeCreatePropertyBlob(fd, &mode, sizeof mode, &atomic->modeBlob_) != 0) {
        why = "drmModeCreatePropertyBlob failed";
        return nullptr;
    }
    return atomic;
}

KmsAtomic::~KmsAtomic() {
    if (modeBlob_ != 0) {
        drmModeDestroyPropertyBlob(fd_, modeBlob_);
    }
}

int KmsAtomic::commit(std::uint32_t fb, bool modeset, void* event) {
    drmModeAtomicReq* request = drmModeAtomicAlloc();
    if (request == nullptr) {
        return -ENOMEM;
    }
    if (modeset) {
        drmModeAtomicAddProperty(request, connectorId_, ids_.connectorCrtcId, crtcId_);
        drmModeAtomicAddProperty(request, crtcId_, ids_.crtcModeId, modeBlob_);
        drmModeAtomicAddProperty(request, crtcId_, ids_.crtcActive, 1);
    }
    drmModeAtomicAddProperty(request, planeId_, ids_.planeFbId, fb);
    drmModeAtomicAddProperty(request, planeId_, ids_.planeCrtcId, crtcId_);
    drmModeAtomicAddProperty(request, planeId_, ids_.srcX, 0);
    drmModeAtomicAddProperty(request, planeId_, ids_.srcY, 0);
    drmModeAtomicAddProperty(request, planeId_, ids_.srcW, std::uint64_t{width_} << 16);
    drmModeAtomicAddProperty(request, planeId_, ids_.srcH, std::uint64_t{height_} << 16);
    drmModeAtomicAddProperty(request, planeId_, ids_.crtcX, 0);
    drmModeAtomicAddProperty(request, planeId_, ids_.crtcY, 0);
    drmModeAtomicAddProperty(request, planeId_, ids_.crtcW, width_);
    drmModeAtomicAddProperty(request, planeId_, ids_.crtcH, height_);
    const std::uint32_t flags = modeset ? DRM_MODE_ATOMIC_ALLOW_MODESET
                                        : DRM_MODE_ATOMIC_NONBLOCK | DRM_MODE_PAGE_FLIP_EVENT;
    const int result = drmModeAtomicCommit(fd_, request, flags, modeset ? nullptr : event);
    const int error = errno;
    drmModeAtomicFree(request);
    return result == 0 ? 0 : -error;
}

}  // namespace vpe::renderer::gles
