// SPDX-License-Identifier: MIT
// SampleBand: a band of rows from every image of a capture, in linear radiance, laid out for
// the fitter: pixels are grouped in chunks of kChunkWidth neighbours (one SIMD vector of the
// fit kernel), and each chunk holds all its samples contiguously —
// [row][chunk][image][channel][lane]. The kernel then streams one contiguous run per chunk
// instead of touching a cache line in each of hundreds of image planes (measured: 2x faster
// fitting at 330 images than a planar [image][channel][row][x] layout).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#include <sys/mman.h>

namespace vpe::capture {

// Storage for a band's arrays.
// - On cache-line boundaries: a chunk's runs are whole cache lines only if the arrays start on
//   one (malloc's 16-byte alignment split every 64-byte run across two lines, so the decoder's
//   streaming stores wrote partial lines and the kernel's vector loads straddled two).
// - Large arrays on 2 MiB huge pages (asked for with madvise; the kernel's default only gives
//   them on request): the decoder writes each image's samples 63 KiB apart (330 images), a
//   new 4 KiB page for every chunk, and the TLB misses (costly under a virtual machine's
//   nested paging) took as long again as the conversion itself (measured: the conversion's
//   time halved).
template <typename T>
struct BandAllocator {
    using value_type = T;
    static constexpr std::size_t kHugePage = std::size_t{2} << 20;
    BandAllocator() = default;
    template <typename U>
    BandAllocator(const BandAllocator<U>&) {}
    static std::size_t alignment(std::size_t bytes) { return bytes >= kHugePage ? kHugePage : 64; }
    static std::size_t rounded(std::size_t bytes) {
        const std::size_t a = alignment(bytes);
        return (bytes + a - 1) / a * a;
    }
    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        void* p = ::operator new (rounded(bytes), std::align_val_t{alignment(bytes)});
        if (bytes >= kHugePage) {
            ::madvise(p, rounded(bytes), MADV_HUGEPAGE);  // a hint: fine if refused
        }
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) {
        ::operator delete (p, std::align_val_t{alignment(n * sizeof(T))});
    }
    friend bool operator==(const BandAllocator&, const BandAllocator&) { return true; }
};

template <typename T>
using BandVector = std::vector<T, BandAllocator<T>>;

struct SampleBand {
    static constexpr int kChannels = 3;
    static constexpr int kChunkWidth = 16;

    int width = 0;
    int chunksPerRow = 0;
    int rowBegin = 0;
    int rows = 0;
    int images = 0;
    BandVector<float> values;            // [row][chunk][image][channel][lane]
    BandVector<float> weights;           // [row][chunk][image][lane]: 1 usable, 0 not
    BandVector<std::uint8_t> saturated;  // [row][chunk][image][lane]: a channel hit full scale
    // [row][chunk]: 1 when every sample of the chunk has weight 1 (the common case), so the
    // fitter can skip loading weights. Set by markFullyUsableChunks().
    std::vector<std::uint8_t> fullyUsable;

    void resize(int imageCount, int imageWidth, int rowCount) {
        images = imageCount;
        width = imageWidth;
        rows = rowCount;
        chunksPerRow = (imageWidth + kChunkWidth - 1) / kChunkWidth;
        const std::size_t samples =
            static_cast<std::size_t>(rows) * chunksPerRow * images * kChunkWidth;
        // Lanes past the row's end keep weight 0.
        values.assign(samples * kChannels, 0.0f);
        weights.assign(samples, 0.0f);
        saturated.assign(samples, 0);
        fullyUsable.assign(static_cast<std::size_t>(rows) * chunksPerRow, 0);
    }

    // As resize(), for a writer that sets every in-range value, weight and saturation flag
    // (ImageBandReader): a band of the same shape keeps its storage without clearing it
    // again, which for 192 MiB per band was only memory traffic. Lanes past the row's end
    // stay zero.
    void prepare(int imageCount, int imageWidth, int rowCount) {
        if (imageCount != images || imageWidth != width || rowCount != rows) {
            resize(imageCount, imageWidth, rowCount);
        }
    }

    void markFullyUsableChunks() {
        const std::size_t perChunk = static_cast<std::size_t>(images) * kChunkWidth;
        for (std::size_t c = 0; c < fullyUsable.size(); ++c) {
            const float* w = weights.data() + c * perChunk;
            fullyUsable[c] = std::all_of(w, w + perChunk, [](float v) { return v == 1.0f; });
        }
    }

    std::size_t chunk(int row, int x) const {
        return static_cast<std::size_t>(row) * chunksPerRow + x / kChunkWidth;
    }
    // Index into weights/saturated of (image, row, x).
    std::size_t sampleIndex(int image, int row, int x) const {
        return (chunk(row, x) * images + image) * kChunkWidth + x % kChunkWidth;
    }
    // Index into values of (image, channel, row, x).
    std::size_t valueIndex(int image, int channel, int row, int x) const {
        return ((chunk(row, x) * images + image) * kChannels + channel) * kChunkWidth +
               x % kChunkWidth;
    }
    float value(int image, int channel, int row, int x) const {
        return values[valueIndex(image, channel, row, x)];
    }
    float weight(int image, int row, int x) const { return weights[sampleIndex(image, row, x)]; }
    bool isSaturated(int image, int row, int x) const {
        return saturated[sampleIndex(image, row, x)] != 0;
    }
};

}  // namespace vpe::capture
