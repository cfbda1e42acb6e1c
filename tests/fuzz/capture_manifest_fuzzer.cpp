// SPDX-License-Identifier: MIT
// libFuzzer target: arbitrary bytes as a capture.json either parse into a well-formed capture
// or fail with an InputError naming the file; anything else crashes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include "vpe/capture/capture_manifest.h"
#include "vpe/common/input_error.h"

namespace {

bool isUnit(const vpe::proto::Vec3d& v) {
    return std::fabs(std::sqrt(vpe::proto::dot(v, v)) - 1.0) < 1e-12;
}

bool isFinite(const vpe::proto::Vec3d& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const vpe::capture::Capture capture =
            vpe::capture::parseCaptureManifest(text, "fuzz/capture.json");
        // What the fitter and the geometry rely on once a manifest is accepted.
        if (capture.images.empty() || !(capture.lightReferenceDistance > 0)) {
            std::abort();
        }
        for (const vpe::capture::CaptureImage& image : capture.images) {
            const bool lightValid = capture.lightKind == vpe::capture::LightKind::kDirectional
                                        ? isUnit(image.light)
                                        : isFinite(image.light);
            if (!lightValid || !(image.intensity > 0) || !std::isfinite(image.intensity)) {
                std::abort();
            }
        }
        if (capture.plane && (!isUnit(capture.plane->normal) || !isFinite(capture.plane->point))) {
            std::abort();
        }
        if (std::holds_alternative<vpe::capture::PinholeCamera>(capture.camera) && !capture.plane &&
            !capture.positionMap) {
            std::abort();
        }
    } catch (const vpe::common::InputError& error) {
        // "capture.json: key: problem" or "capture.json:<line>: invalid JSON: problem".
        if (!std::string_view(error.what()).starts_with("fuzz/capture.json:")) {
            std::abort();
        }
    }
    return 0;
}
