// SPDX-License-Identifier: MIT
// The GLSL ES 3.10 mirrors of the C++ steps a frame takes, one function each, statement for
// statement with its C++ side, so that a shader and the CPU agree to float rounding; each has
// its own GLSL-vs-C++ test (tests/renderer/gles_shading_glsl_test.cpp). Any change to the C++
// side must be made here too.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vpe/proto/bundle_contents.h"
#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer::gles {

// GLSL defining
//   float vpeHorizonFactor(float cosine)            — proto::horizonFactor (surface_horizon.h)
//   vec2 vpeReflectionAngles(vec3 n, vec3 l, vec3 v) — proto::reflectionAngles: (cos θd, cos θs)
//   float vpeThetaTableParameter(float cosThetaS)   — proto::thetaTableParameter (theta_basis.h)
//   float vpeThetaTableCoordinate(float cosThetaS, float scale, float offset)
//                                                   — the same · scale + offset, folded
//   vec3 vpeOctahedralNormal(uint bits)             — decodeOctahedralNormal below
//   vec3 vpeMirroredViewer(vec3 n, vec3 v)          — mirroredViewer below
//   vec2 vpeMirroredReflectionAngles(vec3 n, vec3 l, vec3 m)
//                                                   — (n·l, l·m): reflectionAngles' unclamped
//                                                     cosines from the mirrored viewer
std::string shadingStepsGlsl();

// The viewer's direction mirrored about the shading normal, m = 2(n·v)n − v: proto::
// reflectionAngles' cos θs = 2(n·l)(n·v) − l·v is l·m, and m is fixed per pixel (the viewer does
// not move), so the frame takes one dot product where it normalised v and took three. Unit
// when n and v are.
Vec3d mirroredViewer(const Vec3d& normal, const Vec3d& toViewer);

// The response inverse as a table: compensatePixel's level (ResponseFunction::level, 0 below
// the black level, 1 above 1) per channel at r_i = i/(N − 1), i = 0 … N − 1, rounded to half
// floats as the RGBA16F texture holds them; [3i + c] is channel c of sample i. The frame looks
// it up with one filtered fetch per channel instead of a pow (two SFU operations) or a search.
inline constexpr int kProjectorLevelSamples = 4096;
std::vector<float> projectorLevelTable(const proto::ResponseCurves& response, int samples);
// The table at relative output r, interpolated linearly between samples as GL_LINEAR does and
// clamped at both ends (CLAMP_TO_EDGE): what vpeProjectorLevelTable returns, in double.
double projectorLevelFromTable(const std::vector<float>& table, int channel, double relative);
// GLSL defining the table's sampler `uProjectorLevel` (RGBA16F, cached: 32 KB) and
//   vec3 vpeProjectorLevelTable(vec3 scaled)
// for scaled = r·(N − 1)/N (the frame folds that factor into its uniforms): the coordinate
// scaled + ½/N, below 0 or above 1 the edge samples (0 and 1: the clipping).
std::string projectorLevelTableGlsl(int samples);

// GLSL defining the relief's steps (the relief pass only; proto/detail_normal.h):
//   vec3 vpeDetailNormalFromXy(vec2 xy)              — proto::detailNormalFromXy
//   vec3 vpeApplyDetailNormal(vec3 t, vec3 b, vec3 n, vec3 d)
//                                                   — proto::applyDetailNormal in frame (t, b, n)
std::string reliefStepsGlsl();

// GLSL defining
//   float vpeBilinearWeight(highp sampler2DArray weights, vec2 st, int layer, bool wrapS)
// — a texel-exact bilinear sample of one layer at GL texture coordinate st = (u, 1 − v):
// renderer's bilinearFootprint (material_textures.h; clamp to edge, or repeat in s) with four
// texelFetch, in float: no GPU filter precision involved (8-bit filtering differs by a level
// between GPUs).
std::string bilinearWeightGlsl();

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
