// SPDX-License-Identifier: MIT
// Whole-image I/O with OpenImageIO.
#include "vpe/image/image_file.h"

#include <OpenImageIO/imageio.h>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"

namespace vpe::image {

ImageInfo readImageInfo(const std::filesystem::path& path) {
    auto input = OIIO::ImageInput::open(path.string());
    if (!input) {
        std::string reason = OIIO::geterror();
        throw common::InputError(path, "cannot read image" + (reason.empty() ? "" : ": " + reason));
    }
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
        throw common::InputError(path, "image has no pixels");
    }
    return {spec.width, spec.height, spec.nchannels, static_cast<int>(8 * spec.format.size()),
            spec.format.is_floating_point()};
}

FloatImage readImage(const std::filesystem::path& path) {
    auto input = OIIO::ImageInput::open(path.string());
    if (!input) {
        std::string reason = OIIO::geterror();
        throw common::InputError(path, "cannot read image" + (reason.empty() ? "" : ": " + reason));
    }
    const OIIO::ImageSpec& spec = input->spec();
    FloatImage image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    image.integerSource = !spec.format.is_floating_point();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
        throw common::InputError(path, "image has no pixels");
    }
    image.pixels.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
        throw common::InputError(path, "cannot decode image: " + input->geterror());
    }
    return image;
}

FloatImage readImageChannels(const std::filesystem::path& path,
                             const std::vector<std::string>& channels) {
    auto input = OIIO::ImageInput::open(path.string());
    if (!input) {
        std::string reason = OIIO::geterror();
        throw common::InputError(path, "cannot read image" + (reason.empty() ? "" : ": " + reason));
    }
    const OIIO::ImageSpec& spec = input->spec();
    std::vector<int> indices;
    for (const std::string& name : channels) {
        const int index = spec.channelindex(name);
        if (index < 0) {
            throw common::InputError(path, "no channel '" + name + "'");
        }
        indices.push_back(index);
    }
    std::vector<float> all(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data())) {
        throw common::InputError(path, "cannot decode image: " + input->geterror());
    }
    FloatImage image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels = static_cast<int>(channels.size());
    image.integerSource = !spec.format.is_floating_point();
    const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
    image.pixels.resize(pixels * channels.size());
    for (std::size_t p = 0; p < pixels; ++p) {
        for (std::size_t c = 0; c < indices.size(); ++c) {
            image.pixels[p * channels.size() + c] =
                all[p * static_cast<std::size_t>(spec.nchannels) +
                    static_cast<std::size_t>(indices[c])];
        }
    }
    return image;
}

void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                const std::vector<float>& pixels, PixelFormat format,
                const std::vector<std::string>& channelNames) {
    proto::AtomicFile output(path);
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) {
        throw common::InputError(path, "cannot write this image format: " + OIIO::geterror());
    }
    const OIIO::TypeDesc type = format == PixelFormat::kUint8    ? OIIO::TypeDesc::UINT8
                                : format == PixelFormat::kUint16 ? OIIO::TypeDesc::UINT16
                                                                 : OIIO::TypeDesc::FLOAT;
    OIIO::ImageSpec spec(width, height, channels, type);
    if (!channelNames.empty()) {
        spec.channelnames = channelNames;
        spec.alpha_channel = -1;
    }
    if (format == PixelFormat::kFloat) {
        spec.attribute("compression", "zip");
    }
    // OpenEXR headers otherwise carry the write time, and identical renders (vpe synth with
    // one seed) would differ byte for byte.
    spec.attribute("DateTime", "");
    // OpenImageIO converts float to integer formats by clamping to [0, 1] and scaling.
    if (!out->open(output.temporaryPath().string(), spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
        throw common::InputError(path, "cannot write image: " + out->geterror());
    }
    output.commit();
}

void writeImage8(const std::filesystem::path& path, int width, int height, int channels,
                 const std::vector<std::uint8_t>& pixels) {
    proto::AtomicFile output(path);
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) {
        throw common::InputError(path, "cannot write this image format: " + OIIO::geterror());
    }
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!out->open(output.temporaryPath().string(), spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close()) {
        throw common::InputError(path, "cannot write image: " + out->geterror());
    }
    output.commit();
}

}  // namespace vpe::image
