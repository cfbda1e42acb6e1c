// SPDX-License-Identifier: MIT
// The relief of a capture as a detail normal map: each pixel's normal expressed in the tangent
// frame of the macro shape (proto/detail_normal.h), so that it can travel with the material's
// texels to another object and tilt that object's normals as it tilted the captured one's.
// The macro shape is the normal map low-passed by a local quadratic regression: what a real
// capture knows of its object's shape without a separate scan, and what the relief is measured
// against.
#pragma once

#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/normals/normal_map.h"

namespace vpe::normals {

// The regression window's σ as a share of the image's larger side: chosen on the synthetic
// capture, whose true macro shape is known (docs/transfer-fidelity.md).
inline constexpr double kMacroSigmaShare = 1.0 / 8.0;
double defaultMacroSigma(int width, int height);

// The macro normals: per pixel, the quadratic in the image coordinates that best fits the
// valid normals under a Gaussian window of σ pixels (support ±3σ), taken at the pixel and
// normalized — a low-pass with no bias from the shape's curvature, unlike a plain blur (which
// loses 2 dB of transfer fidelity on the synthetic capture at its best σ). Computed on blocks
// of ⌊σ/8⌋² pixels and interpolated back, so its cost does not grow with σ. Valid where the
// input is.
NormalMap lowPassNormals(const NormalMap& normals, double sigma);

// The world direction of the image's +x axis (the camera's right): the texture's +u on the
// capture. With the macro normal it fixes the tangent frame (t from it, b = n × t ≈ image up).
proto::Vec3d imageRightDirection(const capture::Capture& capture);

// The detail normal of one pixel: the normal's components in the macro normal's frame
// (proto::tangentFrame(macro, right, up), proto::detailNormalIn).
proto::Vec3d detailNormalOf(const proto::Vec3d& normal, const proto::Vec3d& macroNormal,
                            const proto::Vec3d& imageRight);

}  // namespace vpe::normals
