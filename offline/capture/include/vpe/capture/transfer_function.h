// SPDX-License-Identifier: MIT
// TransferFunction: how an image's stored values (codes / full scale) map to linear radiance
// and back. ImageBandReader decodes to linear radiance; what fits the stored values (the RTI
// bases, as RTI tools fit them) encodes them back with the same curve.
#pragma once

#include <string>

#include "vpe/capture/capture.h"

namespace vpe::capture {

struct TransferFunction {
    enum class Kind { kLinear, kSrgb, kGamma };
    Kind kind = Kind::kSrgb;
    double gamma = 1.0;  // kGamma: stored = linear^(1/γ)

    double decode(double stored) const;  // stored value → linear radiance (odd: sign kept)
    double encode(double linear) const;  // linear radiance → stored value (odd: sign kept)
    std::string describe() const;        // "srgb", "linear", "gamma 1.50"
};

// The curve a capture's images were decoded with: declared, or for "auto" sRGB on 8-bit images
// and linear otherwise (ImageBandReader's rule).
TransferFunction storedTransfer(const Capture& capture, bool eightBitImages);

// The curve predictions and images are compared in, "as people see them": sRGB, or the
// images' own stored values when their response was calibrated (ImageEncoding::kGamma) —
// for 8-bit sRGB photographs the two are the same thing.
TransferFunction metricTransfer(const Capture& capture);

}  // namespace vpe::capture
