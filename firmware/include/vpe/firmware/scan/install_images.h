// SPDX-License-Identifier: MIT
// The two small images a node publishes while it captures for the control page's install steps
// (proto/BUS.md, "Install steps"): the camera's view of the white pattern, and the scan's
// coverage map — per camera pixel, whether the projector lights it (white − black, the frame
// check's lit test) and whether its Gray code reads (every Gray pair's pattern and inverse
// differ beyond the noise, all but one allowed to be at a stripe's edge). Both from what the
// capture loop already has in hand, box-averaged to at most 160 pixels wide, as 8-bit grey PNG
// (zlib). The offline decoder (vpe scan) decides per pixel with more care; this is for a person
// looking at a phone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vpe/firmware/scan/camera_image.h"

namespace vpe::firmware {

inline constexpr int kInstallImageWidth = 160;

struct GreyImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels;  // rows from the top
};

// `image` at most `maxWidth` wide (box average; a colour image's Rec. 709 luminance), its
// samples scaled so that maxValue is 255.
GreyImage cameraPreview(const CameraImage& image, int maxWidth = kInstallImageWidth);

// An 8-bit greyscale PNG (one IDAT, zlib's default level).
std::string encodeGreyPng(const GreyImage& image);

class CoverageMap {
public:
    // Values in the map: not lit, lit but its code does not read, lit and decodable.
    static constexpr std::uint8_t kDark = 0, kLit = 96, kDecodable = 255;

    // `minContrast`: white − black, share of full scale, for a pixel to be lit ([scan]
    // min_contrast, as the frame check).
    explicit CoverageMap(double minContrast) : minContrast_(minContrast) {}

    // The white and black captures (one or three channels; the same size).
    void setLit(const CameraImage& white, const CameraImage& black);
    // A Gray pattern and its inverse, after setLit; `noiseSigma` is one frame's noise (samples).
    void addGrayPair(const CameraImage& pattern, const CameraImage& inverse, double noiseSigma);

    bool known() const { return !lit_.empty(); }
    bool hasGrayPairs() const { return pairs_ > 0; }
    double litFraction() const;
    // The share of the camera's pixels that are decodable (0 without Gray pairs).
    double decodableFraction() const;
    // kDark, kLit or kDecodable per pixel (kLit everywhere lit without Gray pairs), box-averaged
    // to at most `maxWidth` wide.
    GreyImage image(int maxWidth = kInstallImageWidth) const;

private:
    bool decodable(std::size_t pixel) const;

    double minContrast_;
    int width_ = 0, height_ = 0;
    std::vector<float> range_;             // white − black, luminance
    std::vector<bool> lit_;                // per pixel
    std::vector<std::uint8_t> undecided_;  // Gray pairs that did not read, per pixel
    int pairs_ = 0;
};

}  // namespace vpe::firmware
