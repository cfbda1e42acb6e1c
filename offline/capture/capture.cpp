// SPDX-License-Identifier: MIT
// Capture helpers.
#include "vpe/capture/capture.h"

#include <algorithm>
#include <cmath>

namespace vpe::capture {

std::optional<Vec3d> unitDirection(const Vec3d& v) {
    const double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (!(largest > 0)) {
        return std::nullopt;
    }
    const Vec3d scaled{v.x / largest, v.y / largest, v.z / largest};
    const double scaledLength = std::sqrt(proto::dot(scaled, scaled));  // in [1, √3]
    if (!(largest * scaledLength > 1e-9)) {
        return std::nullopt;
    }
    return Vec3d{scaled.x / scaledLength, scaled.y / scaledLength, scaled.z / scaledLength};
}

Capture selectHeldOutLights(const Capture& capture, int every, bool heldOut) {
    Capture result = capture;
    result.images.clear();
    for (std::size_t i = 0; i < capture.images.size(); ++i) {
        const bool test =
            every >= 2 && static_cast<int>(i % static_cast<std::size_t>(every)) == every - 1;
        if (test == heldOut) {
            result.images.push_back(capture.images[i]);
        }
    }
    return result;
}

Vec3d PinholeCamera::center() const {
    const auto& r = rotation;
    const Vec3d& t = translation;
    // −Rᵀ t
    return {-(r[0] * t.x + r[3] * t.y + r[6] * t.z), -(r[1] * t.x + r[4] * t.y + r[7] * t.z),
            -(r[2] * t.x + r[5] * t.y + r[8] * t.z)};
}

IncidentLight incidentLight(const Capture& capture, const CaptureImage& image,
                            const Vec3d& surfacePoint) {
    if (capture.lightKind == LightKind::kDirectional) {
        return {image.light, image.intensity};
    }
    const Vec3d d{image.light.x - surfacePoint.x, image.light.y - surfacePoint.y,
                  image.light.z - surfacePoint.z};
    const double distanceSquared = proto::dot(d, d);
    const double reference = capture.lightReferenceDistance;
    return {proto::normalized(d), image.intensity * reference * reference / distanceSquared};
}

}  // namespace vpe::capture
