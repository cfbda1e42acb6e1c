// SPDX-License-Identifier: MIT
// The GLSL ES 3.10 mirrors of the C++ steps a frame takes, one function each, statement for
// statement with its C++ side, so that a shader and the CPU agree to float rounding; each has
// its own GLSL-vs-C++ test (tests/renderer/gles_shading_glsl_test.cpp). Any change to the C++
// side must be made here too.
#pragma once

#include <cstdint>
#include <string>

#include "vpe/proto/bundle_contents.h"
#include "vpe/renderer/vector_types.h"

namespace vpe::renderer::gles {

// GLSL defining
//   float vpeHorizonFactor(float cosine)            — proto::horizonFactor (surface_horizon.h)
//   vec2 vpeReflectionAngles(vec3 n, vec3 l, vec3 v) — proto::reflectionAngles: (cos θd, cos θs)
//   float vpeThetaTableParameter(float cosThetaS)   — proto::thetaTableParameter (theta_basis.h)
//   float vpeThetaTableCoordinate(float cosThetaS, float scale, float offset)
//                                                   — the same · scale + offset, folded
//   vec3 vpeOctahedralNormal(uint bits)             — decodeOctahedralNormal below
std::string shadingStepsGlsl();

// GLSL defining the relief's steps (the relief pass only; proto/detail_normal.h):
//   vec3 vpeDetailNormalFromXy(vec2 xy)              — proto::detailNormalFromXy
//   vec3 vpeApplyDetailNormal(vec3 t, vec3 b, vec3 n, vec3 d)
//                                                   — proto::applyDetailNormal in frame (t, b, n)
std::string reliefStepsGlsl();

// compensateMeasuredPixel (renderer/measured_light.h), the knee kHighlightKnee baked in:
//   vec3 vpeMeasuredOutputs(vec3 target, vec3 irradiance, vec3 floorLight, mat3 mixingInverse)
// and the response inverse through proto::InverseResponseTable of `tableSamples` samples, an
// RGBA16F texture `uInverseResponse` (one filtered fetch per channel):
//   vec3 vpeMeasuredLevel(vec3 relative)
std::string measuredLightGlsl(int tableSamples);

// GLSL defining vec3 vpeProjectorLevel(vec3 relative): the drive levels for wanted relative
// outputs, ResponseFunction::level with compensatePixel's clipping (below the black level →
// 0, above 1 → 1), for this bundle's response only: a gamma compiles to a pow, a sampled
// curve to a search over its samples, baked in as constants (a shader handling both kinds
// behind a uniform pays for both).
std::string projectorLevelGlsl(const proto::ResponseCurves& response);

// A unit vector in 32 bits: octahedral mapping (Meyer et al. 2010), two 16-bit unorms, x in
// the low half (GLSL's packUnorm2x16 order). Angular error below 6e-5 rad. Used for the
// geometric normal, which decides the horizon: its ramp is 0.05 wide in the cosine, and three
// signed 10-bit components (±1e-3) cost the frame tests 5 dB at the terminator.
std::uint32_t encodeOctahedralNormal(const Vec3d& unit);
Vec3d decodeOctahedralNormal(std::uint32_t packed);

// A GLSL float literal that reads back as the same float (9 significant digits).
std::string glslFloat(float value);

}  // namespace vpe::renderer::gles
