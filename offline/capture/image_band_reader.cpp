// SPDX-License-Identifier: MIT
// Streaming band decoder: OpenImageIO scanline reads, transfer function by lookup table.
#include "capture/image_band_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>

#include <OpenImageIO/imageio.h>
#include <sys/resource.h>

#include "vpe/proto/srgb.h"

#include "common/input_error.h"
#include "common/parallel_for.h"

namespace vpe {

namespace {

// Each open image holds a file descriptor; a 330-image capture would exceed common soft
// limits, so raise the soft limit to the hard one once.
void raiseOpenFileLimit() {
    static std::once_flag once;
    std::call_once(once, [] {
        rlimit limit{};
        if (::getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur < limit.rlim_max) {
            limit.rlim_cur = limit.rlim_max;
            ::setrlimit(RLIMIT_NOFILE, &limit);
        }
    });
}

const std::vector<float>& srgbTable(int levels) {
    static const std::vector<float> table8 = [] {
        std::vector<float> t(256);
        for (int i = 0; i < 256; ++i) {
            t[i] = static_cast<float>(proto::srgbToLinear(i / 255.0));
        }
        return t;
    }();
    static const std::vector<float> table16 = [] {
        std::vector<float> t(65536);
        for (int i = 0; i < 65536; ++i) {
            t[i] = static_cast<float>(proto::srgbToLinear(i / 65535.0));
        }
        return t;
    }();
    return levels == 256 ? table8 : table16;
}

}  // namespace

std::string describeImage(const Capture& capture, std::size_t index) {
    const CaptureImage& image = capture.images[index];
    std::string text = image.file.string();
    if (image.line > 0) {
        text += " (" + capture.source.filename().string() + ":" + std::to_string(image.line) + ")";
    }
    return text;
}

struct ImageBandReader::Source {
    std::unique_ptr<OIIO::ImageInput> input;
    std::string description;
    int channels = 0;
    OIIO::TypeDesc readFormat;  // UINT8, UINT16 or FLOAT
    bool srgb = false;
    int nextRow = 0;
    std::vector<unsigned char> scratch;
};

ImageBandReader::ImageBandReader(const Capture& capture, unsigned threads) : threads_(threads) {
    raiseOpenFileLimit();
    sources_.resize(capture.images.size());
    parallelFor(capture.images.size(), 1, threads_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            auto source = std::make_unique<Source>();
            source->description = describeImage(capture, i);
            source->input = OIIO::ImageInput::open(capture.images[i].file.string());
            if (!source->input) {
                const std::string reason = OIIO::geterror();
                if (!std::filesystem::exists(capture.images[i].file)) {
                    throw InputError(source->description + ": no such image file");
                }
                throw InputError(source->description + ": cannot read image" +
                                 (reason.empty() ? "" : ": " + reason));
            }
            const OIIO::ImageSpec& spec = source->input->spec();
            source->channels = spec.nchannels;
            const OIIO::TypeDesc native = spec.format;
            if (native == OIIO::TypeDesc::UINT8) {
                source->readFormat = OIIO::TypeDesc::UINT8;
            } else if (native == OIIO::TypeDesc::UINT16) {
                source->readFormat = OIIO::TypeDesc::UINT16;
            } else {
                source->readFormat = OIIO::TypeDesc::FLOAT;
            }
            switch (capture.encoding) {
                case ImageEncoding::kSrgb:
                    source->srgb = true;
                    break;
                case ImageEncoding::kLinear:
                    source->srgb = false;
                    break;
                case ImageEncoding::kAuto:
                    source->srgb = native == OIIO::TypeDesc::UINT8;
                    break;
            }
            if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
                throw InputError(source->description + ": image has no pixels");
            }
            sources_[i] = std::move(source);
        }
    });
    width_ = sources_.front()->input->spec().width;
    height_ = sources_.front()->input->spec().height;
    for (std::size_t i = 1; i < sources_.size(); ++i) {
        const OIIO::ImageSpec& spec = sources_[i]->input->spec();
        if (spec.width != width_ || spec.height != height_) {
            throw InputError(sources_[i]->description + ": size " + std::to_string(spec.width) +
                             "x" + std::to_string(spec.height) + " differs from " +
                             std::to_string(width_) + "x" + std::to_string(height_) + " of " +
                             sources_.front()->description);
        }
    }
}

ImageBandReader::~ImageBandReader() = default;

int ImageBandReader::width() const {
    return width_;
}
int ImageBandReader::height() const {
    return height_;
}
int ImageBandReader::imageCount() const {
    return static_cast<int>(sources_.size());
}

int ImageBandReader::rowsForBudget(std::size_t budgetBytes) const {
    const std::size_t perRow = sources_.size() * static_cast<std::size_t>(width_ + 16) *
                               (SampleBand::kChannels * sizeof(float) + sizeof(float) + 1);
    return static_cast<int>(std::clamp<std::size_t>(budgetBytes / std::max<std::size_t>(perRow, 1),
                                                    1, static_cast<std::size_t>(height_)));
}

void ImageBandReader::readBand(int rowBegin, int rows, const std::uint8_t* mask, SampleBand& band) {
    band.resize(imageCount(), width_, rows);
    band.rowBegin = rowBegin;
    parallelFor(sources_.size(), 1, threads_, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            Source& source = *sources_[i];
            if (source.nextRow != rowBegin) {
                throw std::logic_error("ImageBandReader: bands must be read in order");
            }
            const int channels = source.channels;
            const std::size_t valueSize = source.readFormat.size();
            source.scratch.resize(static_cast<std::size_t>(width_) * channels * rows * valueSize);
            if (!source.input->read_scanlines(0, 0, rowBegin, rowBegin + rows, 0, 0, channels,
                                              source.readFormat, source.scratch.data())) {
                throw InputError(
                    source.description + ": cannot decode rows " + std::to_string(rowBegin) + ".." +
                    std::to_string(rowBegin + rows - 1) + ": " + source.input->geterror());
            }
            source.nextRow = rowBegin + rows;
            // Grey images feed all three channels; a second or fourth channel is alpha.
            const int colourChannels = channels >= 3 ? 3 : 1;
            for (int r = 0; r < rows; ++r) {
                const std::uint8_t* maskRow =
                    mask ? mask + static_cast<std::size_t>(rowBegin + r) * width_ : nullptr;
                for (int x = 0; x < width_; ++x) {
                    const std::size_t in = (static_cast<std::size_t>(r) * width_ + x) * channels;
                    const int image = static_cast<int>(i);
                    bool usable = maskRow == nullptr || maskRow[x] != 0;
                    bool full = false;
                    for (int c = 0; c < SampleBand::kChannels; ++c) {
                        const std::size_t at = in + (colourChannels == 3 ? c : 0);
                        float value;
                        if (source.readFormat == OIIO::TypeDesc::UINT8) {
                            const std::uint8_t code = source.scratch[at];
                            full |= code == 255;
                            value = source.srgb ? srgbTable(256)[code] : code / 255.0f;
                        } else if (source.readFormat == OIIO::TypeDesc::UINT16) {
                            std::uint16_t code;
                            std::memcpy(&code, source.scratch.data() + at * 2, 2);
                            full |= code == 65535;
                            value = source.srgb ? srgbTable(65536)[code] : code / 65535.0f;
                        } else {
                            std::memcpy(&value, source.scratch.data() + at * 4, 4);
                            if (!std::isfinite(value)) {
                                usable = false;
                                value = 0.0f;
                            } else if (source.srgb) {
                                value = static_cast<float>(
                                    std::copysign(proto::srgbToLinear(std::fabs(value)), value));
                            }
                        }
                        band.values[band.valueIndex(image, c, r, x)] = value;
                    }
                    band.weights[band.sampleIndex(image, r, x)] = usable ? 1.0f : 0.0f;
                    band.saturated[band.sampleIndex(image, r, x)] = full ? 1 : 0;
                }
            }
        }
    });
    band.markFullyUsableChunks();
}

}  // namespace vpe
