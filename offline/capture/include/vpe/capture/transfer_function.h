// SPDX-License-Identifier: MIT
// TransferFunction: how an image's stored values (codes / full scale) map to linear radiance
// and back. ImageBandReader decodes to linear radiance; what fits the stored values (the RTI
// bases, as RTI tools fit them) encodes them back with the same curve.
#pragma once

#include <string>

#include "vpe/capture/capture.h"

namespace vpe {

struct TransferFunction {
    enum class Kind { kLinear, kSrgb };
    Kind kind = Kind::kSrgb;

    double decode(double stored) const;  // stored value → linear radiance (odd: sign kept)
    double encode(double linear) const;  // linear radiance → stored value (odd: sign kept)
    std::string describe() const;        // "srgb", "linear"
};

// The curve a capture's images were decoded with: declared, or for "auto" sRGB on 8-bit images
// and linear otherwise (ImageBandReader's rule).
TransferFunction storedTransfer(const Capture& capture, bool eightBitImages);

}  // namespace vpe
