// SPDX-License-Identifier: MIT
// The capture-specific light-transport factor of the extended model: per texel, a smooth
// function T(l) of the rig's light direction that multiplies the Fourier BRDF to explain
// what the BRDF of (θd, θs) cannot — cast shadows (T < 1) and interreflection (T > 1).
// T belongs to the captured object, not its material: rendering on another shape drops it.
// Basis: real spherical harmonics up to band 3 (16 functions) of the light direction, one
// set per colour channel: light that reaches a texel off coloured surfaces is tinted by
// them, and a dome's lamps differ in colour across their beams (docs/extended-model.md).
#pragma once

#include <array>

#include "vpe/capture/capture.h"

namespace vpe::model {

inline constexpr int kTransportTerms = 16;
inline constexpr int kTransportChannels = 3;  // R, G, B
// Per texel: [channel][term].
inline constexpr int kTransportValues = kTransportChannels * kTransportTerms;

// Writes the 16 basis values for a unit light direction.
void lightTransportBasis(const proto::Vec3d& direction, double* basis);

// Coefficients of T ≡ 1 (no shadowing, no interreflection).
void identityTransport(double* coefficients);

// Each colour channel's T for one light direction, at least 0 (light is never taken away
// below none): `values` holds a texel's kTransportValues.
std::array<double, kTransportChannels> evaluateColourTransport(const float* values,
                                                               const proto::Vec3d& direction);

// The direction a light's transport is indexed by: directional lights as given; point
// lights by their direction from the rig's origin (the object's centre), so that T is a
// function over the dome, independent of where on the object the texel is.
proto::Vec3d transportDirection(const capture::Capture& capture,
                                const capture::CaptureImage& image);

}  // namespace vpe::model
