// SPDX-License-Identifier: MIT
// Transfer functions between stored image values and linear radiance.
#include "vpe/capture/transfer_function.h"

#include <cmath>

#include "vpe/proto/srgb.h"

namespace vpe {

double TransferFunction::decode(double stored) const {
    if (kind == Kind::kLinear) {
        return stored;
    }
    return std::copysign(proto::srgbToLinear(std::fabs(stored)), stored);
}

double TransferFunction::encode(double linear) const {
    if (kind == Kind::kLinear) {
        return linear;
    }
    return std::copysign(proto::linearToSrgb(std::fabs(linear)), linear);
}

std::string TransferFunction::describe() const {
    return kind == Kind::kLinear ? "linear" : "srgb";
}

TransferFunction storedTransfer(const Capture& capture, bool eightBitImages) {
    switch (capture.encoding) {
        case ImageEncoding::kSrgb:
            return {TransferFunction::Kind::kSrgb};
        case ImageEncoding::kLinear:
            return {TransferFunction::Kind::kLinear};
        case ImageEncoding::kAuto:
            break;
    }
    return {eightBitImages ? TransferFunction::Kind::kSrgb : TransferFunction::Kind::kLinear};
}

}  // namespace vpe
