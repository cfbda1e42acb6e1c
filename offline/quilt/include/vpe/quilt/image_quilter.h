// SPDX-License-Identifier: MIT
// Image Quilting (Efros & Freeman 2001) over coefficient maps, restricted to one reflectance
// region: every pixel is a vector of all 2M+2 coefficients × RGB. The output is a position
// map — the source pixel each output pixel copies — since quilting only ever copies pixels;
// the coefficients follow from it. Block search: overlap SSD for every candidate position by
// FFT correlation on a few PCA components (one inverse FFT per block), the best candidates
// re-scored exactly on all channels, one picked at random within (1 + ε) of the best; the
// minimum-error boundary cut by dynamic programming; blocks in a skewed wavefront on all
// threads. Deterministic for a seed whatever the thread count. Optionally toroidal in x, so
// that the texture tiles around a surface whose u wraps.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/model/coefficient_image.h"

namespace vpe::quilt {

// Source coefficient vectors, row-major: values[(y * width + x) * channels + c].
struct QuiltSettings {
    int block = 64;          // block side in pixels
    int overlap = 12;        // overlap width (Efros & Freeman: about a sixth of the block)
    double tolerance = 0.1;  // ε: candidates within (1 + ε) of the best overlap error
    std::uint64_t seed = 1;
    unsigned threads = 1;
    int shortlist = 24;         // candidates re-scored exactly on all channels
    double pcaVariance = 0.95;  // share of the coefficient variance the search components keep
    int maxComponents = 8;
    // Search: kFft is the method; kExhaustive scores every candidate on all channels directly
    // (the baseline the benchmark compares with, and a test oracle).
    enum class Search { kFft, kExhaustive } search = Search::kFft;
    // Tile in x (the texture's u): the output's last column of blocks overlaps its first
    // across x = width | 0, and that seam gets a minimum-error cut like every other overlap,
    // so the texture repeats seamlessly left to right (toroidal placement in x).
    bool wrapU = false;
};

struct RegionQuilt {
    int width = 0;
    int height = 0;
    std::vector<std::int32_t> sourceX;  // per output pixel
    std::vector<std::int32_t> sourceY;
    int block = 0;  // the block size used (smaller than asked if the region is thin)
    int overlap = 0;
    int components = 0;          // PCA components searched
    std::size_t candidates = 0;  // valid block positions in the region
    int blocks = 0;
    bool wrapU = false;  // tiles in x (QuiltSettings::wrapU)
};

// Synthesizes a width × height texture for `region` (pixels of `labels` equal to it). Throws
// InputError when the region cannot hold a block of at least 8 pixels, or when a texture that
// wraps is not wider than one block.
RegionQuilt quiltRegion(const model::CoefficientImage& source,
                        const std::vector<std::uint8_t>& labels, int region, int width, int height,
                        const QuiltSettings& settings);

}  // namespace vpe::quilt
