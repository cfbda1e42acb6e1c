// SPDX-License-Identifier: MIT
// OpenLIME's display of a relit RTI: the decoded value to linear light, an 8-bit offscreen
// buffer, back to sRGB and an 8-bit canvas — what a viewer of an export actually sees.
#pragma once

#include <vector>

namespace vpe::relight_web {

// How OpenLIME (cnr-isti-vclab/openlime, Canvas with its defaults) shows a value its RTI
// shader decoded (RelightWebReader::decode):
// 1. ShaderRTI's "light" mode converts it to linear light, pow(c, 2.2) (the Canvas default
//    isSrgbSimplified: a plain 2.2 power, not the sRGB curve);
// 2. the Canvas renders every layer into an offscreen framebuffer with an RGBA,
//    UNSIGNED_BYTE texture (useOffscreenFramebuffer, on by default): clamped to [0, 1],
//    8 bits — in linear light, so every c below (0.5/255)^(1/2.2) ≈ 0.059 is stored as 0
//    and the next code is shown as 21/255;
// 3. a full-screen pass converts back, pow(x, 1/2.2), clamps and writes the 8-bit canvas.
// pow() of a negative c is undefined in GLSL (a GPU may show anything); it is taken as 0,
// what SwiftShader's NaN becomes in an 8-bit buffer. Returns the canvas value in [0, 1].
float openLimeDisplayed(float decoded);

// openLimeDisplayed() of every value, in place.
void showAsOpenLime(std::vector<float>& values);

}  // namespace vpe::relight_web
