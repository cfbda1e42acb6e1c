// SPDX-License-Identifier: MIT
// synthesizeCapture: `vpe synth`. Photographs the built-in pottery scene on a light rig and
// writes DIR/train and DIR/test (captures `vpe fit` and `vpe eval` read: capture.json with
// the pinhole camera, point lights, true normals and positions) and DIR/truth (normals,
// material labels, per-pixel parameters, the light list). Deterministic for a seed,
// whatever the thread count; DIR appears complete or not at all.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace vpe::synth {

enum class SynthNoise {
    kNone,
    kCamera,  // shot noise (5000 e⁻ at full scale) + read noise (σ = 0.002 of full scale)
};

enum class SynthEncoding {
    kLinear16,  // 16-bit linear PNG
    kExr,       // 32-bit float OpenEXR
    kSrgb8,     // 8-bit sRGB PNG (quantization as a real 8-bit camera)
};

enum class SynthReflectance {
    kMicrofacet,  // GGX + Smith + Schlick + Lambert: not in the Fourier family
    kFourier,     // the Fourier model itself (truth/fourier.exr holds the coefficients)
};

struct SynthOptions {
    std::filesystem::path out;
    int size = 128;
    std::uint64_t seed = 1;
    std::string rig = "paper";  // paper | dome
    SynthNoise noise = SynthNoise::kNone;
    bool shadows = true;
    SynthEncoding encoding = SynthEncoding::kLinear16;
    SynthReflectance reflectance = SynthReflectance::kMicrofacet;
    int fourierHarmonics = 4;
    unsigned threads = 1;
};

struct SynthReport {
    int trainImages = 0;
    int testImages = 0;
    int size = 0;
    double streakFraction = 0;    // share of pixels labelled streak
    double shadowedFraction = 0;  // share of lit samples the relief shadows
    double clippedFraction = 0;   // share of samples clipped at full scale
    double seconds = 0;
};

SynthReport synthesizeCapture(const SynthOptions& options);

}  // namespace vpe::synth
