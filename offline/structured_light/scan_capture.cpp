// SPDX-License-Identifier: MIT
// Opening a scan folder: the manifest through proto's reader, images through OpenImageIO.
#include "vpe/structured_light/scan_capture.h"

#include <set>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/luminance.h"

namespace vpe::structured_light {

namespace {

proto::ScanManifest readManifest(const std::filesystem::path& path) {
    std::error_code code;
    if (!std::filesystem::is_directory(path, code) && path.filename() != proto::kScanManifestName) {
        throw common::InputError(path, std::filesystem::exists(path, code)
                                           ? "not a scan folder (a folder holding scan.json)"
                                           : "no such scan folder");
    }
    return proto::readScanManifest(path);
}

}  // namespace

ScanCapture::ScanCapture(const std::filesystem::path& folderOrManifest)
    : folder_(proto::scanFolderOf(folderOrManifest)),
      manifest_(readManifest(folderOrManifest)),
      sequence_(manifest_.patterns) {
    std::set<std::string> listed;
    for (std::size_t i = 0; i < manifest_.images.size(); ++i) {
        listed.insert(manifest_.images[i].file);
        imageOfPattern_.emplace(manifest_.images[i].pattern, i);
        std::error_code error;
        if (!std::filesystem::is_regular_file(imagePath(i), error)) {
            throw common::InputError(imagePath(i), "missing: the scan's image of pattern '" +
                                                       manifest_.images[i].pattern + "'");
        }
    }
    // A pattern image the manifest does not list is a capture that went wrong (a retry left
    // behind, two scans in one folder): refused rather than ignored.
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(folder_, error)) {
        const std::string name = entry.path().filename().string();
        const std::string stem = entry.path().stem().string();
        if (listed.contains(name) || !entry.is_regular_file()) {
            continue;
        }
        for (const proto::PatternSpec& pattern : sequence_.patterns()) {
            if (stem == pattern.name() || stem.ends_with("-" + pattern.name())) {
                throw common::InputError(entry.path(), std::string("an extra pattern image that ") +
                                                           proto::kScanManifestName +
                                                           " does not list");
            }
        }
    }
}

std::vector<float> greyPixels(image::FloatImage picture, const std::filesystem::path& source) {
    if (picture.channels == 1) {
        return std::move(picture.pixels);
    }
    if (picture.channels < 3) {
        throw common::InputError(
            source, std::to_string(picture.channels) + " channels (a scan image is grey or RGB)");
    }
    std::vector<float> grey(static_cast<std::size_t>(picture.width) * picture.height);
    for (std::size_t p = 0; p < grey.size(); ++p) {
        const float* rgb = &picture.pixels[p * static_cast<std::size_t>(picture.channels)];
        grey[p] = static_cast<float>(proto::luminance709(rgb[0], rgb[1], rgb[2]));
    }
    return grey;
}

std::filesystem::path ScanCapture::imagePath(std::size_t index) const {
    return folder_ / manifest_.images.at(index).file;
}

std::vector<float> ScanCapture::image(std::size_t index) const {
    const std::filesystem::path path = imagePath(index);
    image::FloatImage image = image::readImage(path);
    if (image.width != width() || image.height != height()) {
        throw common::InputError(
            path, std::to_string(image.width) + "x" + std::to_string(image.height) +
                      ", but the manifest's camera is " + std::to_string(width()) + "x" +
                      std::to_string(height()));
    }
    return greyPixels(std::move(image), path);
}

std::size_t ScanCapture::imageIndex(std::string_view pattern) const {
    const auto found = imageOfPattern_.find(pattern);
    if (found == imageOfPattern_.end()) {
        throw common::InputError(folder_,
                                 "the sequence has no pattern '" + std::string(pattern) + "'");
    }
    return found->second;
}

std::vector<float> ScanCapture::image(const char* name) const {
    return image(imageIndex(name));
}

}  // namespace vpe::structured_light
