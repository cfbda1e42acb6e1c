// SPDX-License-Identifier: MIT
// GrayCodePattern capture folders (procam-calibration's layout) into vpe scan folders.
#include "vpe/structured_light/graycode_import.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <iterator>
#include <map>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::structured_light {

namespace {

constexpr std::string_view kPrefix = "graycode_";
constexpr std::string_view kExtension = ".png";

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
std::string imageName(std::size_t index) {
    return std::string(kPrefix) + (index < 10 ? "0" : "") + std::to_string(index) +
           std::string(kExtension);
}

// NN of a file named graycode_NN.png (the tool's names), or −1 for any other file.
long imageIndexOf(const std::string& name) {
    if (!name.starts_with(kPrefix) || !name.ends_with(kExtension) ||
        name.size() <= kPrefix.size() + kExtension.size()) {
        return -1;
    }
    const std::string_view digits(name.data() + kPrefix.size(),
                                  name.size() - kPrefix.size() - kExtension.size());
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
        images.push_back({imageName(i), order[i], 1});
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
    for (const auto& entry : std::filesystem::directory_iterator(capture)) {
        const long index = imageIndexOf(entry.path().filename().string());
        if (index < 0) {
            continue;  // the tool's other files (a calibration result, notes)
        }
        if (const auto [place, added] = found.emplace(index, entry.path()); !added) {
            throw common::InputError(entry.path(), "image " + std::to_string(index) + " again (" +
                                                       place->second.filename().string() + ")");
        }
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
        if (info.floating || info.bits != 8) {
            throw common::InputError(path, std::to_string(info.bits) + "-bit " +
                                               (info.floating ? "float" : "integer") +
                                               " samples: vpe reads 8-bit captures of this tool");
        }
        if (i == 0) {
            manifest.camera.width = info.width;
            manifest.camera.height = info.height;
            manifest.camera.bits = 8;
        } else if (info.width != manifest.camera.width || info.height != manifest.camera.height) {
            throw common::InputError(
                path, std::to_string(info.width) + "x" + std::to_string(info.height) + ", but " +
                          images[0].file + " is " + std::to_string(manifest.camera.width) + "x" +
                          std::to_string(manifest.camera.height));
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
