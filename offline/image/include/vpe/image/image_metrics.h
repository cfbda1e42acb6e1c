// SPDX-License-Identifier: MIT
// How alike two pictures are as people see them: both 8-bit sRGB (linear radiance × exposure,
// clamped, sRGB-encoded, rounded), compared over a mask — PSNR and SSIM (Wang, Bovik, Sheikh
// and Simoncelli 2004: Gaussian window 11 × 11, σ = 1.5, K1 = 0.01, K2 = 0.03, L = 255), SSIM on
// each of R, G and B and averaged.
#pragma once

#include <cstdint>
#include <vector>

namespace vpe::image {

// Interleaved RGB, row 0 at the top.
struct Rgb8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> values;  // 3 per pixel
};

// Linear RGB (3 floats a pixel) × exposure → 8-bit sRGB, as pictures for people are written.
Rgb8Image toSrgb8(const std::vector<float>& linearRgb, int width, int height, double exposure);

// 10·log10(255² / MSE) over the masked pixels' channels; +∞ when they are equal, NaN when the
// mask is empty. Sizes must agree (std::invalid_argument otherwise).
double psnr(const Rgb8Image& a, const Rgb8Image& b, const std::vector<std::uint8_t>& mask);

// The SSIM map's mean over the masked pixels whose whole 11 × 11 window lies in the image (the
// "valid" map of the reference implementation), averaged over R, G and B; NaN when there is no
// such pixel.
double meanSsim(const Rgb8Image& a, const Rgb8Image& b, const std::vector<std::uint8_t>& mask);

// The SSIM map of one channel (c = 0, 1, 2), width × height, NaN where the window leaves the
// image. For tests and pictures.
std::vector<double> ssimMap(const Rgb8Image& a, const Rgb8Image& b, int channel);

}  // namespace vpe::image
