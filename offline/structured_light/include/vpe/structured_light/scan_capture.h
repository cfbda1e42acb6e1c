// SPDX-License-Identifier: MIT
// ScanCapture: a scan folder (proto/SCAN.md) opened and checked — its manifest, and its images
// read one at a time as the camera's linear-or-not signal in [0, 1] (monochrome: colour
// images are reduced to Rec. 709 luminance).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/image/image_file.h"
#include "vpe/proto/scan_manifest.h"

namespace vpe::structured_light {

// A picture's grey values (Rec. 709 luminance of a colour one). Throws InputError naming `source`
// for a picture of 2 channels.
std::vector<float> greyPixels(image::FloatImage picture, const std::filesystem::path& source);

class ScanCapture {
public:
    // Reads the manifest and checks that every image it names exists (and that the folder holds
    // no other pattern image: a file named like one of the sequence's patterns but not listed).
    // Throws InputError "PATH: problem" naming the manifest or the image.
    explicit ScanCapture(const std::filesystem::path& folderOrManifest);

    const proto::ScanManifest& manifest() const { return manifest_; }
    const proto::StructuredLightSequence& sequence() const { return sequence_; }
    const std::filesystem::path& folder() const { return folder_; }
    int width() const { return manifest_.camera.width; }
    int height() const { return manifest_.camera.height; }
    // The manifest's image `index` (the manifest lists them in any order).
    std::filesystem::path imagePath(std::size_t index) const;
    // The manifest's index of the image showing the pattern named `pattern` ("white",
    // "gray-x-b10", …). Throws InputError naming the folder when the sequence has no such
    // pattern.
    std::size_t imageIndex(std::string_view pattern) const;

    // The manifest's image `index`, width·height values. Throws InputError naming the file when
    // it cannot be read or its size is not the manifest's camera size.
    std::vector<float> image(std::size_t index) const;
    // The image of the pattern named `name`.
    std::vector<float> image(const char* name) const;

private:
    std::filesystem::path folder_;
    proto::ScanManifest manifest_;
    proto::StructuredLightSequence sequence_;
    std::map<std::string, std::size_t, std::less<>> imageOfPattern_;
};

}  // namespace vpe::structured_light
