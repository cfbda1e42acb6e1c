// SPDX-License-Identifier: MIT
// The synthetic capture's ground-truth reflectance: Lambert diffuse plus a Cook-Torrance
// specular lobe with the GGX (Trowbridge-Reitz) distribution, height-correlated Smith
// shadowing-masking and Schlick's Fresnel. It depends on the half vector, not on (θd, θs)
// alone, so the Fourier model can only approximate it: fitting errors are honest.
#pragma once

#include "vpe/capture/capture.h"

namespace vpe::synth {

struct MicrofacetMaterial {
    proto::Vec3d albedo{0.5, 0.5, 0.5};  // diffuse reflectance ρ per channel
    double roughness = 0.3;              // GGX α (perceptual roughness squared)
    double f0 = 0.04;  // Fresnel reflectance at normal incidence (dielectric glaze)
};

// Radiance leaving the surface towards `toViewer` under a light of unit irradiance
// (perpendicular to the light) from `toLight`, scaled by π so that a white Lambertian
// surface lit head-on returns 1: (ρ + π f_spec) · max(n·l, 0) per channel. Unit vectors.
proto::Vec3d microfacetRadiance(const MicrofacetMaterial& material, const proto::Vec3d& normal,
                                const proto::Vec3d& toLight, const proto::Vec3d& toViewer);

// The pieces, exposed for the closed-form tests.
double ggxDistribution(double cosThetaH, double alpha);
double smithHeightCorrelatedVisibility(double cosThetaL, double cosThetaV, double alpha);
double schlickFresnel(double f0, double cosThetaD);

}  // namespace vpe::synth
