// SPDX-License-Identifier: MIT
// The camera's own response, measured from exposure brackets: every radiometric measurement
// vpe makes goes through the camera, so a camera whose codes are not proportional to light (an
// ISP's 8-bit output, gamma-encoded) must be linearized first (docs/radiometry.md).
// CameraLinearization is the code → linear signal table; fitCameraResponse measures it from
// photographs of a static scene at several exposures (Debevec & Malik 1997, through OpenCV's photo
// module); the CSV functions keep it beside a capture.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace vpe::radiometry {

// One photograph of a static scene at a relative exposure (any unit, e.g. microseconds: only
// the ratios between a bracket's exposures matter).
struct BracketedImage {
    int width = 0, height = 0, channels = 1;  // 1 or 3 (interleaved RGB)
    int maxValue = 255;                       // only 8-bit data can be bracketed (OpenCV's Debevec)
    std::vector<std::uint16_t> samples;       // width·height·channels, rows from the top
    double exposure = 1;
};

// Code → linear signal, per channel: a table of maxValue + 1 entries per channel, monotone
// non-decreasing, with linear(maxValue) = 1 in every channel.
//
// Why 1 at each channel's own top code, not one scale for all channels: bracketing measures
// each channel's curve up to a factor of its own (Debevec's g(z) is fixed only up to an added
// constant per channel; OpenCV pins each channel's middle code to 1), so the ratios between the
// channels' scales are not measured at all, and any common scale would only carry OpenCV's
// arbitrary choice of pin. The channels' relative gains (the white balance) come from a white
// reference, measured through this table; the table itself says "fraction of the signal that
// takes this channel to its top code", as ResponseInput's curves say "fraction of the
// channel's full output".
class CameraLinearization {
public:
    // Linear data: code / maxValue. maxValue ≥ 1, channels 1 or 3 (std::invalid_argument).
    static CameraLinearization identity(int maxValue, int channels);
    // One table per channel (1 or 3), all of the same length ≥ 2 (maxValue + 1 entries):
    // finite, ≥ 0, monotone non-decreasing, ending at exactly 1 and starting below it. Throws
    // InputError naming the channel and code otherwise.
    static CameraLinearization fromTables(std::vector<std::vector<double>> tables);

    int channels() const { return static_cast<int>(tables_.size()); }
    int maxValue() const { return static_cast<int>(tables_.front().size()) - 1; }
    // Every table is code / maxValue (to within rounding): the data need no linearizing.
    bool isLinear() const { return linear_; }

    // std::out_of_range for a channel or code outside the table.
    double linear(int channel, int code) const;
    const std::vector<double>& table(int channel) const;

private:
    explicit CameraLinearization(std::vector<std::vector<double>> tables);

    std::vector<std::vector<double>> tables_;
    bool linear_ = false;
};

// Debevec & Malik's response recovery through cv::createCalibrateDebevec, from at least 3
// images of one static scene with distinct exposures, all of one size and channel count, 8-bit.
// Monochrome images are fitted as one channel. It fits 100 pixels chosen across the scene's
// range of brightness, each where the image is smooth (camera_response.cpp says why not
// OpenCV's grid). Codes those pixels never show (below the darkest; above the brightest short
// of 255, where the sensor clips) are extrapolated as power laws of the codes next to them,
// code 0 going to 0, and the read noise's wiggles at the dark end are made monotone. Throws
// InputError with one line naming what is wrong: "bracket: 2 images; at least 3 exposures are
// needed", "bracket: image 3 is 640x480, the others 1640x1232", "bracket: images 1 and 2 have
// the same exposure 500; exposures must differ", "bracket: image 1 is 10-bit (maxValue 1023);
// only 8-bit images …", and for a scene too flat to fit: fewer than 16 pixels of distinct
// brightness, or a channel showing fewer than 32 codes.
CameraLinearization fitCameraResponse(std::span<const BracketedImage> images);

// The table as CSV: a "code,value" (one channel) or "code,r,g,b" header, then one row per code
// from 0 to maxValue; written atomically, numbers in the shortest form that reads back exactly.
void writeCameraResponseCsv(const std::filesystem::path& path, const CameraLinearization& response);
// Reads what writeCameraResponseCsv writes: blank lines and # comments are skipped, the header
// is optional, codes must run 0, 1, … without gaps. Throws InputError "PATH:LINE: problem", or
// "PATH: problem" for what fromTables refuses.
CameraLinearization readCameraResponseCsv(const std::filesystem::path& path);

}  // namespace vpe::radiometry
