// SPDX-License-Identifier: MIT
// Streaming band decoder: OpenImageIO scanline reads, transfer function by lookup table.
#include "vpe/capture/image_band_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include <OpenImageIO/imageio.h>
#include <immintrin.h>
#include <sys/resource.h>

#include "vpe/capture/decoded_image_cache.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/proto/srgb.h"

namespace vpe::capture {

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

// Code → linear value tables. The linear ones hold exactly code / full-scale in float (what a
// division would give), so a lookup changes no value.
template <int kLevels>
std::vector<float> makeTable(bool srgb) {
    std::vector<float> table(kLevels);
    for (int i = 0; i < kLevels; ++i) {
        table[static_cast<std::size_t>(i)] =
            srgb ? static_cast<float>(proto::srgbToLinear(i / static_cast<double>(kLevels - 1)))
                 : static_cast<float>(i) / static_cast<float>(kLevels - 1);
    }
    return table;
}
const std::vector<float>& srgbTable8() {
    static const std::vector<float> table = makeTable<256>(true);
    return table;
}
const std::vector<float>& linearTable8() {
    static const std::vector<float> table = makeTable<256>(false);
    return table;
}
const std::vector<float>& srgbTable16() {
    static const std::vector<float> table = makeTable<65536>(true);
    return table;
}

// Rows of one image as OpenImageIO decoded them (interleaved channels), and where they go.
struct DecodedRows {
    const unsigned char* data;
    std::size_t rowBytes;
    int channels;
    int image;
    int rowBegin;
    int rows;
    int width;
    const std::uint8_t* mask;  // W × H of the whole image, or null
};

constexpr std::size_t kImagesPerFlagLine = 64 / SampleBand::kChunkWidth;

// Grey images feed all three channels; a second or fourth channel is alpha.
int colourStep(int channels) {
    return channels >= 3 ? 1 : 0;
}

// Writes a chunk's three channel runs and weights (whole cache lines) past the caches: the
// band is far larger than them and is read once, by the fitter, so fetching each line before
// overwriting it (as ordinary stores do) only doubled the memory traffic.
[[gnu::always_inline]] inline void streamChunk(const float (&chunk)[4][SampleBand::kChunkWidth],
                                               float* values, float* weights) {
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < SampleBand::kChunkWidth; i += 4) {
            _mm_stream_ps(values + c * SampleBand::kChunkWidth + i, _mm_load_ps(&chunk[c][i]));
        }
    }
    for (int i = 0; i < SampleBand::kChunkWidth; i += 4) {
        _mm_stream_ps(weights + i, _mm_load_ps(&chunk[3][i]));
    }
}

// Where one chunk of up to kChunkWidth pixels of a decoded row goes in the band: its three
// channel runs, its weights and its saturation flags, and the mask row it is read with.
struct ChunkTarget {
    const unsigned char* row;     // the decoded row
    const std::uint8_t* maskRow;  // the mask's row, or null
    int x0;                       // first pixel of the chunk
    int lanes;                    // pixels in it (the last chunk of a row may be short)
    float* values;
    float* weights;
    std::uint8_t* saturated;
};

// Calls convert(target) for every chunk of the decoded rows, row by row.
template <typename Convert>
[[gnu::always_inline]] inline void forEachChunk(const DecodedRows& in, SampleBand& band,
                                                Convert convert) {
    constexpr int kLanes = SampleBand::kChunkWidth;
    for (int r = 0; r < in.rows; ++r) {
        ChunkTarget t{};
        t.row = in.data + in.rowBytes * r;
        t.maskRow =
            in.mask ? in.mask + static_cast<std::size_t>(in.rowBegin + r) * in.width : nullptr;
        for (t.x0 = 0; t.x0 < in.width; t.x0 += kLanes) {
            t.lanes = std::min(kLanes, in.width - t.x0);
            t.values = band.values.data() + band.valueIndex(in.image, 0, r, t.x0);
            t.weights = band.weights.data() + band.sampleIndex(in.image, r, t.x0);
            t.saturated = band.saturated.data() + band.sampleIndex(in.image, r, t.x0);
            convert(t);
        }
    }
}

// Integer codes through a table, one chunk of kChunkWidth pixels at a time: the chunk's three
// channel runs and its weights are contiguous in the band, so each is written in one pass.
// (Converting value by value through SampleBand's index helpers took ten times as long as
// decoding the JPEG.)
template <typename Code, typename ToLinear>
[[gnu::always_inline]] inline void convertCodes(const DecodedRows& in, ToLinear toLinear,
                                                SampleBand& band) {
    constexpr int kLanes = SampleBand::kChunkWidth;
    constexpr Code kFull = std::numeric_limits<Code>::max();
    const int step = colourStep(in.channels);
    forEachChunk(
        in, band, [&](const ChunkTarget& t) __attribute__((always_inline)) {
            const Code* row = reinterpret_cast<const Code*>(t.row);
            alignas(16) float chunk[4][kLanes] = {};  // R, G, B runs and the weights
            for (int lane = 0; lane < t.lanes; ++lane) {
                const Code* pixel = row + static_cast<std::size_t>(t.x0 + lane) * in.channels;
                const Code red = pixel[0], green = pixel[step], blue = pixel[2 * step];
                chunk[0][lane] = toLinear(red);
                chunk[1][lane] = toLinear(green);
                chunk[2][lane] = toLinear(blue);
                chunk[3][lane] = t.maskRow == nullptr || t.maskRow[t.x0 + lane] != 0 ? 1.0f : 0.0f;
                t.saturated[lane] = (red == kFull) | (green == kFull) | (blue == kFull);
            }
            streamChunk(chunk, t.values, t.weights);
        });
    _mm_sfence();
}

// Each format's conversion, built for x86-64-v4, v3 and baseline like the fitting kernel
// (picked at run time): the clones do the same integer and IEEE operations, so the same values.
#define VPE_CONVERSION_CLONES \
    __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))

VPE_CONVERSION_CLONES
void convertCodes8(const DecodedRows& in, const float* table, SampleBand& band) {
    convertCodes<std::uint8_t>(
        in, [table](std::uint8_t code) { return table[code]; }, band);
}

VPE_CONVERSION_CLONES
void convertCodes16(const DecodedRows& in, const float* table, SampleBand& band) {
    convertCodes<std::uint16_t>(
        in, [table](std::uint16_t code) { return table[code]; }, band);
}

// Linear 16-bit codes are computed, not looked up: a 256 KiB table does not stay in L1. The
// same expression as the tables', so the same values.
VPE_CONVERSION_CLONES
void convertLinear16(const DecodedRows& in, SampleBand& band) {
    convertCodes<std::uint16_t>(
        in, [](std::uint16_t code) { return static_cast<float>(code) / 65535.0f; }, band);
}

// Floating-point images: a sample with a non-finite channel is unusable (value 0).
VPE_CONVERSION_CLONES
void convertFloats(const DecodedRows& in, bool srgb, SampleBand& band) {
    constexpr int kLanes = SampleBand::kChunkWidth;
    const int step = colourStep(in.channels);
    forEachChunk(
        in, band, [&](const ChunkTarget& t) __attribute__((always_inline)) {
            const float* row = reinterpret_cast<const float*>(t.row);
            for (int lane = 0; lane < t.lanes; ++lane) {
                const float* pixel = row + static_cast<std::size_t>(t.x0 + lane) * in.channels;
                bool usable = t.maskRow == nullptr || t.maskRow[t.x0 + lane] != 0;
                for (int c = 0; c < SampleBand::kChannels; ++c) {
                    float value = pixel[c * step];
                    if (!std::isfinite(value)) {
                        usable = false;
                        value = 0.0f;
                    } else if (srgb) {
                        value = static_cast<float>(
                            std::copysign(proto::srgbToLinear(std::fabs(value)), value));
                    }
                    t.values[c * kLanes + lane] = value;
                }
                t.saturated[lane] = 0;
                t.weights[lane] = usable ? 1.0f : 0.0f;
            }
        });
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
    std::filesystem::path file;
    std::unique_ptr<OIIO::ImageInput> input;  // null when decoded already (cached)
    std::string description;
    int width = 0;
    int height = 0;
    int channels = 0;
    OIIO::TypeDesc readFormat;  // UINT8, UINT16 or FLOAT
    bool srgb = false;
    const float* table = nullptr;  // integer codes → linear radiance, when not the defaults
    int nextRow = 0;
    std::vector<unsigned char> scratch;
    // The image as an earlier reader decoded it (DecodedImageCache), or, while this reader
    // decodes it, the whole image it fills for the cache (when the cache admits it).
    std::shared_ptr<const DecodedImageCache::Image> cached;
    std::shared_ptr<DecodedImageCache::Image> filling;
};

namespace {

OIIO::TypeDesc formatOfValueBytes(int bytes) {
    return bytes == 1 ? OIIO::TypeDesc::UINT8
                      : (bytes == 2 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::FLOAT);
}

}  // namespace

ImageBandReader::ImageBandReader(const Capture& capture, unsigned threads) : threads_(threads) {
    raiseOpenFileLimit();
    if (capture.encoding == ImageEncoding::kGamma) {
        const TransferFunction response = storedTransfer(capture, true);
        gammaTable8_.resize(256);
        for (int i = 0; i < 256; ++i) {
            gammaTable8_[static_cast<std::size_t>(i)] =
                static_cast<float>(response.decode(i / 255.0));
        }
        gammaTable16_.resize(65536);
        for (int i = 0; i < 65536; ++i) {
            gammaTable16_[static_cast<std::size_t>(i)] =
                static_cast<float>(response.decode(i / 65535.0));
        }
    }
    sources_.resize(capture.images.size());
    const auto open = [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            auto source = std::make_unique<Source>();
            source->file = capture.images[i].file;
            source->description = describeImage(capture, i);
            source->cached = DecodedImageCache::instance().find(source->file);
            if (source->cached) {
                source->width = source->cached->width;
                source->height = source->cached->height;
                source->channels = source->cached->channels;
                source->readFormat = formatOfValueBytes(source->cached->valueBytes);
            } else {
                source->input = OIIO::ImageInput::open(source->file.string());
                if (!source->input) {
                    const std::string reason = OIIO::geterror();
                    if (!std::filesystem::exists(source->file)) {
                        throw common::InputError(source->description + ": no such image file");
                    }
                    throw common::InputError(source->description + ": cannot read image" +
                                             (reason.empty() ? "" : ": " + reason));
                }
                const OIIO::ImageSpec& spec = source->input->spec();
                source->width = spec.width;
                source->height = spec.height;
                source->channels = spec.nchannels;
                const OIIO::TypeDesc native = spec.format;
                if (native == OIIO::TypeDesc::UINT8) {
                    source->readFormat = OIIO::TypeDesc::UINT8;
                } else if (native == OIIO::TypeDesc::UINT16) {
                    source->readFormat = OIIO::TypeDesc::UINT16;
                } else {
                    source->readFormat = OIIO::TypeDesc::FLOAT;
                }
            }
            // Read as 8-bit exactly when stored so: "auto" decodes those as sRGB.
            const bool eightBit = source->readFormat == OIIO::TypeDesc::UINT8;
            switch (capture.encoding) {
                case ImageEncoding::kSrgb:
                    source->srgb = true;
                    break;
                case ImageEncoding::kLinear:
                    source->srgb = false;
                    break;
                case ImageEncoding::kAuto:
                    source->srgb = eightBit;
                    break;
                case ImageEncoding::kGamma:
                    if (source->readFormat == OIIO::TypeDesc::FLOAT) {
                        throw common::InputError(
                            source->description +
                            ": a calibrated camera response applies to integer "
                            "images only");
                    }
                    source->table = source->readFormat == OIIO::TypeDesc::UINT8
                                        ? gammaTable8_.data()
                                        : gammaTable16_.data();
                    break;
            }
            if (source->width <= 0 || source->height <= 0 || source->channels <= 0) {
                throw common::InputError(source->description + ": image has no pixels");
            }
            sources_[i] = std::move(source);
        }
    };
    // The first image alone, then the rest in parallel: OpenImageIO 2.4 builds its EXIF and
    // XMP tag tables on the first JPEG it opens, without a lock. Opened concurrently, photos
    // with metadata (loewenkopf, realrti-dev) raced there (helgrind: writes to the tables in
    // one thread, reads in another) and a fit crashed, rarely, in the fresh-install demo.
    if (!capture.images.empty()) {
        open(0, 1);
    }
    common::parallelFor(capture.images.size() > 0 ? capture.images.size() - 1 : 0, 1, threads_,
                        [&](std::size_t begin, std::size_t end) { open(begin + 1, end + 1); });
    width_ = sources_.front()->width;
    height_ = sources_.front()->height;
    for (std::size_t i = 1; i < sources_.size(); ++i) {
        const Source& source = *sources_[i];
        if (source.width != width_ || source.height != height_) {
            throw common::InputError(source.description + ": size " + std::to_string(source.width) +
                                     "x" + std::to_string(source.height) + " differs from " +
                                     std::to_string(width_) + "x" + std::to_string(height_) +
                                     " of " + sources_.front()->description);
        }
    }
    keepDecodedImages();
}

// The images this reader decodes are kept for the next reader (DecodedImageCache) when the
// whole capture fits the cache's budget; a larger one streams, its memory growing with the band.
void ImageBandReader::keepDecodedImages() {
    std::size_t total = 0;
    for (const auto& source : sources_) {
        total += static_cast<std::size_t>(source->width) * source->height * source->channels *
                 source->readFormat.size();
    }
    if (!DecodedImageCache::instance().admits(total)) {
        return;
    }
    for (const auto& source : sources_) {
        if (source->cached) {
            continue;
        }
        source->filling = std::make_shared<DecodedImageCache::Image>();
        source->filling->width = source->width;
        source->filling->height = source->height;
        source->filling->channels = source->channels;
        source->filling->valueBytes = static_cast<int>(source->readFormat.size());
        source->filling->bytes.resize(static_cast<std::size_t>(source->width) * source->height *
                                      source->channels * source->readFormat.size());
    }
}

// A reader made before another one decoded its images (the fit's, made before photometric
// stereo reads the capture) takes them from the cache when it starts reading: the same bytes,
// without decoding the file again.
void ImageBandReader::adoptDecodedImage(Source& source) {
    std::shared_ptr<const DecodedImageCache::Image> decoded =
        DecodedImageCache::instance().find(source.file);
    if (decoded && decoded->width == source.width && decoded->height == source.height &&
        decoded->channels == source.channels &&
        decoded->valueBytes == static_cast<int>(source.readFormat.size())) {
        source.cached = std::move(decoded);
        source.filling.reset();
        source.input.reset();
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

bool ImageBandReader::eightBitCodes() const {
    return std::all_of(sources_.begin(), sources_.end(), [](const std::unique_ptr<Source>& source) {
        return source->readFormat == OIIO::TypeDesc::UINT8;
    });
}

int ImageBandReader::rowsForBudget(std::size_t budgetBytes) const {
    const std::size_t perRow = sources_.size() * static_cast<std::size_t>(width_ + 16) *
                               (SampleBand::kChannels * sizeof(float) + sizeof(float) + 1);
    return static_cast<int>(std::clamp<std::size_t>(budgetBytes / std::max<std::size_t>(perRow, 1),
                                                    1, static_cast<std::size_t>(height_)));
}

void ImageBandReader::readBand(int rowBegin, int rows, const std::uint8_t* mask, SampleBand& band) {
    band.prepare(imageCount(), width_, rows);
    band.rowBegin = rowBegin;
    // Four images per task: their saturation flags share cache lines (16 bytes a chunk each),
    // which two threads writing neighbouring images would pass back and forth.
    common::parallelFor(
        sources_.size(), kImagesPerFlagLine, threads_, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                Source& source = *sources_[i];
                if (source.nextRow != rowBegin) {
                    throw std::logic_error("ImageBandReader: bands must be read in order");
                }
                if (rowBegin == 0 && !source.cached) {
                    adoptDecodedImage(source);
                }
                const int channels = source.channels;
                const std::size_t valueSize = source.readFormat.size();
                const std::size_t rowBytes =
                    static_cast<std::size_t>(width_) * channels * valueSize;
                const std::size_t offset = static_cast<std::size_t>(rowBegin) * rowBytes;
                // Decoded once per process where the cache holds the image (or will).
                std::shared_ptr<const DecodedImageCache::Image> held = source.cached;
                const unsigned char* rowsData = held ? held->bytes.data() + offset : nullptr;
                if (!held) {
                    unsigned char* target = nullptr;
                    if (source.filling) {
                        target = source.filling->bytes.data() + offset;
                    } else {
                        source.scratch.resize(rowBytes * rows);
                        target = source.scratch.data();
                    }
                    if (!source.input->read_scanlines(0, 0, rowBegin, rowBegin + rows, 0, 0,
                                                      channels, source.readFormat, target)) {
                        throw common::InputError(source.description + ": cannot decode rows " +
                                                 std::to_string(rowBegin) + ".." +
                                                 std::to_string(rowBegin + rows - 1) + ": " +
                                                 source.input->geterror());
                    }
                    rowsData = target;
                    if (source.filling && rowBegin + rows == height_) {
                        held = source.filling;  // alive until converted, whatever the cache does
                        DecodedImageCache::instance().insert(source.file,
                                                             std::move(source.filling));
                    }
                }
                source.nextRow = rowBegin + rows;
                const DecodedRows decoded{rowsData, rowBytes, channels, static_cast<int>(i),
                                          rowBegin, rows,     width_,   mask};
                if (source.table != nullptr && source.readFormat == OIIO::TypeDesc::UINT8) {
                    convertCodes8(decoded, source.table, band);
                } else if (source.table != nullptr) {
                    convertCodes16(decoded, source.table, band);
                } else if (source.readFormat == OIIO::TypeDesc::UINT8) {
                    convertCodes8(decoded,
                                  source.srgb ? srgbTable8().data() : linearTable8().data(), band);
                } else if (source.readFormat == OIIO::TypeDesc::UINT16 && source.srgb) {
                    convertCodes16(decoded, srgbTable16().data(), band);
                } else if (source.readFormat == OIIO::TypeDesc::UINT16) {
                    convertLinear16(decoded, band);
                } else {
                    convertFloats(decoded, source.srgb, band);
                }
            }
        });
    band.markFullyUsableChunks();
}

}  // namespace vpe::capture
