// SPDX-License-Identifier: MIT
// The GLSL mirror of proto's Fourier BRDF (see the header).
#include "vpe/renderer/gles/fourier_brdf_glsl.h"

#include "vpe/proto/fourier_brdf.h"

namespace vpe::renderer::gles {

std::string fourierBrdfGlsl(int harmonics) {
    return "#define VPE_HARMONICS " + std::to_string(harmonics) + "\n" + R"GLSL(
const int VPE_COEFFICIENTS = 2 * VPE_HARMONICS + 2;
const float VPE_CONSTANT_BASIS = 0.70710678118654752440;  // 1/sqrt(2), proto::kConstantBasis

// proto::evaluateFourierBrdf: the Chebyshev recurrence of proto::HarmonicRecurrence, the
// specular sum in the same order, then kd * max(cos θd, 0) + a0 / sqrt(2) + specular.
vec3 vpeFourierBrdf(vec3 coefficients[VPE_COEFFICIENTS], float cosThetaD, float cosThetaS) {
    float c = min(max(cosThetaS, -1.0), 1.0);
    float twoC = c + c;
    float cosPrev = 1.0;
    float cosCur = c;
    float sinPrev = 0.0;
    float sinCur = sqrt(max(1.0 - c * c, 0.0));
    vec3 specular = vec3(0.0);
    for (int m = 1; m <= VPE_HARMONICS; ++m) {
        specular = specular + coefficients[2 * m] * cosCur + coefficients[2 * m + 1] * sinCur;
        float cosNext = twoC * cosCur - cosPrev;
        float sinNext = twoC * sinCur - sinPrev;
        cosPrev = cosCur;
        cosCur = cosNext;
        sinPrev = sinCur;
        sinCur = sinNext;
    }
    return coefficients[0] * max(cosThetaD, 0.0) + coefficients[1] * VPE_CONSTANT_BASIS +
           specular;
}

// proto::reflectionAngles: (cos θd = n·l, cos θs = 2(n·l)(n·v) − l·v clamped to [−1, 1]).
vec2 vpeReflectionAngles(vec3 normal, vec3 toLight, vec3 toViewer) {
    float nl = dot(normal, toLight);
    float rv = 2.0 * nl * dot(normal, toViewer) - dot(toLight, toViewer);
    return vec2(nl, min(max(rv, -1.0), 1.0));
}
)GLSL";
}

std::string fourierBasisGlsl(int harmonics) {
    const auto index = [](int k) { return "basis[" + std::to_string(k) + "]"; };
    std::string s = R"GLSL(
// proto::fourierBasis: the basis values, f = Σ_k coefficients[k]·basis[k] per channel:
// max(cos θd, 0), 1/√2, then cos mθs and sin mθs by HarmonicRecurrence's steps, unrolled.
void vpeFourierBasis(float cosThetaD, float cosThetaS, out float basis[VPE_COEFFICIENTS]) {
    basis[0] = max(cosThetaD, 0.0);
    basis[1] = VPE_CONSTANT_BASIS;
)GLSL";
    if (harmonics > 0) {
        s += "    float c = min(max(cosThetaS, -1.0), 1.0);\n"
             "    float twoC = c + c;\n"
             "    basis[2] = c;\n"
             "    basis[3] = sqrt(max(1.0 - c * c, 0.0));\n";
    }
    for (int m = 2; m <= harmonics; ++m) {
        const int cosine = proto::cosineIndex(m), sine = proto::sineIndex(m);
        s += "    " + index(cosine) + " = twoC * " + index(cosine - 2) + " - " +
             (m == 2 ? std::string("1.0") : index(cosine - 4)) + ";\n";
        s += "    " + index(sine) + " = twoC * " + index(sine - 2) +
             (m == 2 ? std::string("") : " - " + index(sine - 4)) + ";\n";
    }
    return s + "}\n";
}

static_assert(proto::kLambertIndex == 0 && proto::kConstantIndex == 1 &&
                  proto::cosineIndex(1) == 2 && proto::sineIndex(1) == 3,
              "fourierBrdfGlsl hard-codes fourier_brdf.h's coefficient layout");

}  // namespace vpe::renderer::gles
