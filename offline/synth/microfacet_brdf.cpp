// SPDX-License-Identifier: MIT
// GGX + Smith + Schlick + Lambert.
#include "vpe/synth/microfacet_brdf.h"

#include <algorithm>
#include <cmath>

namespace vpe::synth {

double ggxDistribution(double cosThetaH, double alpha) {
    const double a2 = alpha * alpha;
    const double d = cosThetaH * cosThetaH * (a2 - 1.0) + 1.0;
    return a2 / (M_PI * d * d);
}

// V = G / (4 n·l n·v), height-correlated form (Heitz 2014).
double smithHeightCorrelatedVisibility(double cosThetaL, double cosThetaV, double alpha) {
    const double a2 = alpha * alpha;
    const double lambdaV = cosThetaL * std::sqrt(cosThetaV * cosThetaV * (1.0 - a2) + a2);
    const double lambdaL = cosThetaV * std::sqrt(cosThetaL * cosThetaL * (1.0 - a2) + a2);
    return 0.5 / (lambdaV + lambdaL);
}

double schlickFresnel(double f0, double cosThetaD) {
    const double m = std::clamp(1.0 - cosThetaD, 0.0, 1.0);
    const double m2 = m * m;
    return f0 + (1.0 - f0) * m2 * m2 * m;
}

proto::Vec3d microfacetRadiance(const MicrofacetMaterial& material, const proto::Vec3d& normal,
                                const proto::Vec3d& toLight, const proto::Vec3d& toViewer) {
    const double nl = proto::dot(normal, toLight);
    const double nv = proto::dot(normal, toViewer);
    if (nl <= 0.0 || nv <= 0.0) {
        return {0, 0, 0};
    }
    const proto::Vec3d half = proto::normalized(
        proto::Vec3d{toLight.x + toViewer.x, toLight.y + toViewer.y, toLight.z + toViewer.z});
    const double nh = std::max(proto::dot(normal, half), 0.0);
    const double lh = std::max(proto::dot(toLight, half), 0.0);
    const double alpha = std::max(material.roughness, 1e-3);
    const double specular = ggxDistribution(nh, alpha) *
                            smithHeightCorrelatedVisibility(nl, nv, alpha) *
                            schlickFresnel(material.f0, lh);
    const double s = M_PI * specular;
    return {(material.albedo.x + s) * nl, (material.albedo.y + s) * nl,
            (material.albedo.z + s) * nl};
}

}  // namespace vpe::synth
