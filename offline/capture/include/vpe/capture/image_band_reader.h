// SPDX-License-Identifier: MIT
// ImageBandReader: streams the images of a capture in bands of rows, so memory grows with
// N × W × band height, never N × W × H. Every image stays open and is decoded once, top to
// bottom (OpenImageIO scanline reads: JPEG, PNG, TIFF and OpenEXR decode incrementally); the
// images of a band are decoded on all threads, and the result does not depend on how many.
// A capture that fits DecodedImageCache's budget is kept decoded for the process: an extended
// fit reads it up to seven times, and only the first pass decodes the files.
#pragma once

#include <memory>

#include "vpe/capture/capture.h"
#include "vpe/capture/sample_band.h"

namespace vpe::capture {

class ImageBandReader {
public:
    // Opens every image and checks that they decode and share one size. Throws InputError
    // naming the image (and the line of the light file that listed it).
    ImageBandReader(const Capture& capture, unsigned threads);
    ~ImageBandReader();
    ImageBandReader(const ImageBandReader&) = delete;
    ImageBandReader& operator=(const ImageBandReader&) = delete;

    int width() const;
    int height() const;
    int imageCount() const;
    // True when every image stores 8-bit codes ("auto" decodes them as sRGB).
    bool eightBitCodes() const;

    // Reads rows [rowBegin, rowBegin + rows) of every image into band; bands must be read in
    // order. `mask` (W × H, nonzero = use) may be null.
    void readBand(int rowBegin, int rows, const std::uint8_t* mask, SampleBand& band);

    // A band height that keeps one band near `budgetBytes`.
    int rowsForBudget(std::size_t budgetBytes) const;

private:
    struct Source;
    void keepDecodedImages();
    static void adoptDecodedImage(Source& source);
    std::vector<std::unique_ptr<Source>> sources_;
    unsigned threads_;
    std::vector<float> gammaTable8_, gammaTable16_;  // a calibrated response (kGamma)
    int width_ = 0;
    int height_ = 0;
};

// Names an image of a capture in messages: "image07.jpg (dirs.lp:8)".
std::string describeImage(const Capture& capture, std::size_t index);

}  // namespace vpe::capture
