// SPDX-License-Identifier: MIT
// The classic RTI bases researchers compare against: Polynomial Texture Maps (Malzbender et
// al. 2001; 6 or 10 terms, polynomials in the light's x and y) and Hemispherical Harmonics
// (Gautron et al. 2004; 4, 9, 16 or 25 terms over the upper hemisphere). Per pixel and
// colour channel, the stored image value under a light l is Σ_k c_k b_k(l): a fit of the
// appearance of one object under one rig, not a material (nothing in it transfers to
// another shape). `vpe fit --model ptm6|hsh16` fits them, `vpe eval` scores them.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "vpe/capture/capture.h"

namespace vpe::model {

struct RtiBasis {
    enum class Kind { kPtm, kHsh };
    Kind kind = Kind::kHsh;
    int terms = 16;

    static constexpr int kMaxTerms = 25;

    // "ptm6", "ptm10", "hsh4", "hsh9", "hsh16", "hsh25"; "ptm" and "hsh" alone mean 6 and 16.
    // Nothing for anything else.
    static std::optional<RtiBasis> parse(std::string_view spec);
    std::string name() const;  // "ptm6"

    // Writes the `terms` basis values for a unit direction towards the light (x right, y up,
    // z towards the camera).
    void evaluate(const proto::Vec3d& light, double* out) const;
};

}  // namespace vpe::model
