// SPDX-License-Identifier: MIT
// The GLSL ES 3.10 mirror of proto/include/vpe/proto/fourier_brdf.h and reflection_geometry.h:
// the same basis order, recurrence and clamping, statement for statement, so that a shader and
// proto::evaluateFourierBrdf<float> agree to float rounding (tests/renderer/gles_brdf_test.cpp
// evaluates both on random inputs). Any change to proto's model must be made here too.
#pragma once

#include <string>

namespace vpe::renderer::gles {

// GLSL source defining, for a given M (baked in as VPE_HARMONICS):
//   const int VPE_COEFFICIENTS = 2 * VPE_HARMONICS + 2;
//   vec3 vpeFourierBrdf(vec3 coefficients[VPE_COEFFICIENTS], float cosThetaD, float cosThetaS)
//     — f per colour channel, coefficients in fourier_brdf.h's order kd, a0, a1, b1, …, aM, bM;
//   vec2 vpeReflectionAngles(vec3 normal, vec3 toLight, vec3 toViewer) — (cos θd, cos θs).
// To be pasted after the #version and precision lines.
std::string fourierBrdfGlsl(int harmonics);

// GLSL source, to follow fourierBrdfGlsl(harmonics), defining
//   void vpeFourierBasis(float cosThetaD, float cosThetaS, out float basis[VPE_COEFFICIENTS])
//     — the basis values of that evaluation (max(cos θd, 0), 1/√2, cos θs, sin θs, cos 2θs, …,
//     the same recurrence, unrolled for M), so that f = Σ_k coefficients[k]·basis[k]: a
//     shader can then evaluate f in any linear image of the coefficients (a low-rank code).
std::string fourierBasisGlsl(int harmonics);

}  // namespace vpe::renderer::gles
