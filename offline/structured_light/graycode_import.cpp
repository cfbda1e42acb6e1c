// SPDX-License-Identifier: MIT
// GrayCodePattern capture folders (procam-calibration's layout) into vpe scan folders.
#include "vpe/structured_light/graycode_import.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <iterator>
#include <map>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::structured_light {

namespace {

constexpr std::string_view kPrefix = "graycode_";
// The formats the tool's cameras write that vpe reads: one per capture folder.
constexpr std::array<std::string_view, 5> kExtensions = {".png", ".jpg", ".jpeg", ".tif", ".tiff"};

proto::StructuredLightSequence sequenceOf(const GrayCodeProjector& projector) {
    proto::StructuredLightParameters parameters;
    parameters.width = projector.width;
    parameters.height = projector.height;
    parameters.phaseSteps = 0;
    parameters.codeStep = projector.codeStep;
    try {
        return proto::StructuredLightSequence(parameters);
    } catch (const proto::StructuredLightError& error) {
        throw common::InputError("--projector " + std::to_string(projector.width) + "x" +
                                 std::to_string(projector.height) + " --step " +
                                 std::to_string(projector.codeStep) + ": " + error.what());
    }
}

// "a 1024x768 projector with step 1 shows 42 images (2·(10 + 10) + 2)"
std::string whatTheProjectorShows(const GrayCodeProjector& projector) {
    const proto::StructuredLightSequence sequence = sequenceOf(projector);
    return "a " + std::to_string(projector.width) + "x" + std::to_string(projector.height) +
           " projector with step " + std::to_string(projector.codeStep) + " shows " +
           std::to_string(sequence.patterns().size()) + " images (2·(" +
           std::to_string(sequence.grayBits(proto::PatternAxis::kColumns)) + " + " +
           std::to_string(sequence.grayBits(proto::PatternAxis::kRows)) + ") + 2)";
}

// The tool's name of image `index`: two digits at least ("graycode_07.png").
std::string imageName(std::size_t index, const std::string& extension) {
    return std::string(kPrefix) + (index < 10 ? "0" : "") + std::to_string(index) + extension;
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

// NN of a file named graycode_NN.EXT (the tool's names), or −1 for any other file.
long imageIndexOf(const std::filesystem::path& file) {
    const std::string stem = file.stem().string();
    if (!stem.starts_with(kPrefix) || stem.size() == kPrefix.size() ||
        file.extension().string().size() < 2) {
        return -1;
    }
    const std::string_view digits(stem.data() + kPrefix.size(), stem.size() - kPrefix.size());
    long index = -1;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    return error == std::errc() && end == digits.data() + digits.size() ? index : -1;
}

}  // namespace

std::vector<proto::ScanImage> grayCodeImages(const GrayCodeProjector& projector) {
    const proto::StructuredLightSequence sequence = sequenceOf(projector);
    // The tool's order is the device's Gray pairs, with white and black last.
    std::vector<std::string> order;
    for (const proto::PatternSpec& pattern : sequence.patterns()) {
        if (pattern.kind == proto::PatternKind::kGray) {
            order.push_back(pattern.name());
        }
    }
    order.insert(order.end(), {"white", "black"});
    std::vector<proto::ScanImage> images;
    for (std::size_t i = 0; i < order.size(); ++i) {
        images.push_back({imageName(i, ".png"), order[i], 1});
    }
    return images;
}

proto::ScanManifest importGrayCodeCapture(const std::filesystem::path& capture,
                                          const GrayCodeProjector& projector,
                                          const std::filesystem::path& into) {
    std::vector<proto::ScanImage> images = grayCodeImages(projector);
    std::error_code error;
    if (!std::filesystem::is_directory(capture, error)) {
        throw common::InputError(capture, std::filesystem::exists(capture, error)
                                              ? "not a folder (a capture folder of graycode_NN.png)"
                                              : "no such capture folder");
    }
    std::map<long, std::filesystem::path> found;
    // The first file of each extension (lowercase), to name two when they differ.
    std::map<std::string, std::filesystem::path> byExtension;
    for (const auto& entry : std::filesystem::directory_iterator(capture)) {
        const long index = imageIndexOf(entry.path());
        if (index < 0) {
            continue;  // the tool's other files (a calibration result, notes)
        }
        const std::string extension = lowercase(entry.path().extension().string());
        if (std::find(kExtensions.begin(), kExtensions.end(), extension) == kExtensions.end()) {
            throw common::InputError(entry.path(),
                                     "not an image format vpe imports (.png, .jpg, .jpeg, .tif, "
                                     ".tiff: 8-bit, or 16-bit PNG and TIFF)");
        }
        if (const auto [place, added] = found.emplace(index, entry.path()); !added) {
            throw common::InputError(entry.path(), "image " + std::to_string(index) + " again (" +
                                                       place->second.filename().string() + ")");
        }
        const auto [first, added] = byExtension.emplace(extension, entry.path());
        if (!added && entry.path().filename() < first->second.filename()) {
            first->second = entry.path();
        }
    }
    if (byExtension.size() > 1) {
        // Named in order: "graycode_00.png, graycode_07.jpg".
        std::vector<std::filesystem::path> firsts;
        for (const auto& [extension, path] : byExtension) {
            firsts.push_back(path);
        }
        std::sort(firsts.begin(), firsts.end());
        std::string names;
        for (const std::filesystem::path& path : firsts) {
            names += (names.empty() ? "" : ", ") + path.filename().string();
        }
        throw common::InputError(capture, "mixes image formats (" + names +
                                              "): one format for every graycode image of a "
                                              "capture");
    }
    const std::string extension =
        byExtension.empty() ? ".png" : found.begin()->second.extension().string();
    for (std::size_t i = 0; i < images.size(); ++i) {
        images[i].file = imageName(i, extension);
    }
    const std::string count =
        std::to_string(found.size()) + " graycode images, " + whatTheProjectorShows(projector);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const auto place = found.find(static_cast<long>(i));
        if (place == found.end()) {
            throw common::InputError(capture / images[i].file, "missing (pattern '" +
                                                                   images[i].pattern +
                                                                   "'): the folder "
                                                                   "holds " +
                                                                   count);
        }
        images[i].file = place->second.filename().string();
    }
    if (found.size() > images.size()) {
        throw common::InputError(std::prev(found.end())->second,
                                 "an extra image: the folder holds " + count);
    }

    proto::ScanManifest manifest;
    manifest.patterns = sequenceOf(projector).parameters();
    manifest.createdBy = "vpe import-graycode";
    manifest.camera.exposureUs = 0;  // not recorded by the tool
    manifest.camera.analogueGain = 0;
    manifest.camera.source = "opencv-graycode:" + std::filesystem::absolute(capture).string();
    for (std::size_t i = 0; i < images.size(); ++i) {
        const std::filesystem::path path = capture / images[i].file;
        const image::ImageInfo info = image::readImageInfo(path);
        if (info.floating || (info.bits != 8 && info.bits != 16)) {
            throw common::InputError(path, std::to_string(info.bits) + "-bit " +
                                               (info.floating ? "float" : "integer") +
                                               " samples: vpe reads 8- or 16-bit integer captures "
                                               "of this tool");
        }
        if (i == 0) {
            manifest.camera.width = info.width;
            manifest.camera.height = info.height;
            manifest.camera.bits = info.bits;
        } else if (info.width != manifest.camera.width || info.height != manifest.camera.height) {
            throw common::InputError(
                path, std::to_string(info.width) + "x" + std::to_string(info.height) + ", but " +
                          images[0].file + " is " + std::to_string(manifest.camera.width) + "x" +
                          std::to_string(manifest.camera.height));
        } else if (info.bits != manifest.camera.bits) {
            throw common::InputError(path, std::to_string(info.bits) + "-bit, but " +
                                               images[0].file + " is " +
                                               std::to_string(manifest.camera.bits) +
                                               "-bit: one depth for every image of a capture");
        }
    }
    manifest.images = std::move(images);
    std::filesystem::create_directories(into);
    for (const proto::ScanImage& image : manifest.images) {
        std::filesystem::copy_file(capture / image.file, into / image.file);
    }
    proto::writeScanManifest(into, manifest);
    return manifest;
}

}  // namespace vpe::structured_light
