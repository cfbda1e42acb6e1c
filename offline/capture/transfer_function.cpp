// SPDX-License-Identifier: MIT
// Transfer functions between stored image values and linear radiance.
#include "vpe/capture/transfer_function.h"

#include <cmath>
#include <cstdio>

#include "vpe/proto/srgb.h"

namespace vpe::capture {

double TransferFunction::decode(double stored) const {
    if (kind == Kind::kLinear) {
        return stored;
    }
    if (kind == Kind::kGamma) {
        return std::copysign(std::pow(std::fabs(stored), gamma), stored);
    }
    return std::copysign(proto::srgbToLinear(std::fabs(stored)), stored);
}

double TransferFunction::encode(double linear) const {
    if (kind == Kind::kLinear) {
        return linear;
    }
    if (kind == Kind::kGamma) {
        return std::copysign(std::pow(std::fabs(linear), 1.0 / gamma), linear);
    }
    return std::copysign(proto::linearToSrgb(std::fabs(linear)), linear);
}

std::string TransferFunction::describe() const {
    if (kind == Kind::kGamma) {
        char text[32];
        std::snprintf(text, sizeof text, "gamma %.2f", gamma);
        return text;
    }
    return kind == Kind::kLinear ? "linear" : "srgb";
}

TransferFunction storedTransfer(const Capture& capture, bool eightBitImages) {
    switch (capture.encoding) {
        case ImageEncoding::kSrgb:
            return {TransferFunction::Kind::kSrgb};
        case ImageEncoding::kLinear:
            return {TransferFunction::Kind::kLinear};
        case ImageEncoding::kGamma:
            return {TransferFunction::Kind::kGamma, capture.gamma};
        case ImageEncoding::kAuto:
            break;
    }
    return {eightBitImages ? TransferFunction::Kind::kSrgb : TransferFunction::Kind::kLinear};
}

TransferFunction metricTransfer(const Capture& capture) {
    if (capture.encoding == ImageEncoding::kGamma) {
        return {TransferFunction::Kind::kGamma, capture.gamma};
    }
    return {TransferFunction::Kind::kSrgb};
}

}  // namespace vpe::capture
