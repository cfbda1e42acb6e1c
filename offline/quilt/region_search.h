// SPDX-License-Identifier: MIT
// The quilter's per-region search structures (private to quilt/): the region's bounds and
// valid block positions, its coefficient vectors projected on a few principal components, and
// their spectra for FFT correlation, plus an integral image of the projections' energy. Built
// once per region; the quilter (image_quilter.cpp) reads them for every block.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include <fftw3.h>

#include "vpe/quilt/image_quilter.h"

namespace vpe::quilt::search {

// FFTW's aligned buffers.
struct FftwFree {
    void operator()(void* p) const { fftwf_free(p); }
};
using RealBuffer = std::unique_ptr<float, FftwFree>;
using ComplexBuffer = std::unique_ptr<fftwf_complex, FftwFree>;

inline RealBuffer allocateReal(std::size_t n) {
    return RealBuffer(fftwf_alloc_real(n));
}
inline ComplexBuffer allocateComplex(std::size_t n) {
    return ComplexBuffer(fftwf_alloc_complex(n));
}

// Sums over axis-aligned boxes in O(1).
class IntegralImage {
public:
    IntegralImage(int width, int height)
        : width_(width), sums_((width + 1) * static_cast<std::size_t>(height + 1), 0.0) {}
    void build(const std::vector<double>& values, int height) {
        for (int y = 0; y < height; ++y) {
            double row = 0;
            for (int x = 0; x < width_; ++x) {
                row += values[static_cast<std::size_t>(y) * width_ + x];
                at(x + 1, y + 1) = at(x + 1, y) + row;
            }
        }
    }
    double sum(int x0, int y0, int x1, int y1) const {  // [x0, x1) × [y0, y1)
        return get(x1, y1) - get(x0, y1) - get(x1, y0) + get(x0, y0);
    }

private:
    double& at(int x, int y) { return sums_[static_cast<std::size_t>(y) * (width_ + 1) + x]; }
    double get(int x, int y) const { return sums_[static_cast<std::size_t>(y) * (width_ + 1) + x]; }
    int width_;
    std::vector<double> sums_;
};

// The overlap of a block with what is already placed: strips along its left, top and right
// sides, each given by its width in pixels (0: none). A right strip only exists when the
// output wraps in x: the last block of a row overlaps the first one across the seam.
struct OverlapShape {
    int left = 0;
    int top = 0;
    int right = 0;
    bool any() const { return left > 0 || top > 0 || right > 0; }
    bool contains(int qx, int qy, int block) const {
        return qx < left || qy < top || qx >= block - right;
    }
    auto key() const { return std::tuple{left, top, right}; }
};

// Everything about one region that does not change from block to block.
class RegionSearch {
public:
    // The search structures are built only when the region holds at least `enough`
    // candidates: a block size that will be refused costs no PCA and no spectra.
    RegionSearch(const model::CoefficientImage& source, const std::vector<std::uint8_t>& labels,
                 int region, int block, const QuiltSettings& settings, std::size_t enough);
    ~RegionSearch();
    RegionSearch(const RegionSearch&) = delete;
    RegionSearch& operator=(const RegionSearch&) = delete;

    // Whether the FFT search structures were built (else every candidate is scored directly).
    bool usesFft() const { return useFft_; }
    std::size_t candidateCount() const { return candidateCount_; }
    // Valid block positions, row by row: py * positionsX() + px.
    const std::vector<std::uint32_t>& candidateList() const { return candidateList_; }
    int components() const { return components_; }
    int boundsX() const { return bx_; }
    int boundsY() const { return by_; }
    int positionsX() const { return bw_ - block_ + 1; }
    int positionsY() const { return bh_ - block_ + 1; }
    bool valid(int px, int py) const {
        return valid_[static_cast<std::size_t>(py) * positionsX() + px] != 0;
    }
    // The i-th valid candidate, for picking a first block.
    std::pair<int, int> candidate(std::size_t i) const {
        const auto at = static_cast<int>(candidateList_[i]);
        return {at % positionsX(), at / positionsX()};
    }
    // PCA components of source pixel (x, y) (image coordinates).
    const float* projected(int x, int y) const {
        return projected_.data() +
               (static_cast<std::size_t>(y - by_) * bw_ + (x - bx_)) * components_;
    }
    int fftWidth() const { return fw_; }
    int fftHeight() const { return fh_; }
    std::size_t spectrumSize() const { return static_cast<std::size_t>(fh_) * (fw_ / 2 + 1); }
    const fftwf_complex* spectrum(int k) const {
        return spectra_[static_cast<std::size_t>(k)].get();
    }
    fftwf_plan inverse() const { return inverse_; }
    // A template's forward transform in two passes: rows (only the first `block` rows hold
    // anything; the rest transform to zero and are skipped), then columns, out of place from
    // a buffer whose other rows stay zero. About half the cost of the full 2-D transform.
    fftwf_plan templateRows() const { return templateRows_; }
    fftwf_plan templateColumns() const { return templateColumns_; }
    // Σ over the overlap shape, at candidate p, of the squared PCA components: the strips'
    // sums less their corners (left and right never meet: each is under half a block).
    double overlapEnergy(int px, int py, const OverlapShape& shape) const {
        const int x = px, y = py;  // bounding-box coordinates of the block's corner
        const int b = block_;
        double e = 0;
        if (shape.left > 0) {
            e += squares_->sum(x, y, x + shape.left, y + b);
        }
        if (shape.right > 0) {
            e += squares_->sum(x + b - shape.right, y, x + b, y + b);
        }
        if (shape.top > 0) {
            e += squares_->sum(x, y, x + b, y + shape.top);
            if (shape.left > 0) {
                e -= squares_->sum(x, y, x + shape.left, y + shape.top);
            }
            if (shape.right > 0) {
                e -= squares_->sum(x + b - shape.right, y, x + b, y + shape.top);
            }
        }
        return e;
    }

private:
    void findBounds(const std::vector<std::uint8_t>& labels, int region);
    void findCandidates(const std::vector<std::uint8_t>& labels, int region);
    // Principal components of the region's coefficient vectors: the search runs on the few
    // that hold most of the variance (SSD of differences is unchanged by centring).
    void buildProjection(const std::vector<std::uint8_t>& labels, int region,
                         const QuiltSettings& settings);
    // FFTs of the region's PCA components, padded to an FFT-friendly size. Cyclic correlation
    // is exact for every valid block: a candidate corner plus a block offset stays inside.
    void buildSpectra();

    const model::CoefficientImage& source_;
    int block_;
    int bx_ = 0, by_ = 0, bw_ = 0, bh_ = 0, fw_ = 0, fh_ = 0;
    std::vector<std::uint8_t> valid_;
    std::vector<std::uint32_t> candidateList_;
    std::size_t candidateCount_ = 0;
    bool useFft_ = false;
    int components_ = 0;
    std::vector<float> projected_;
    std::unique_ptr<IntegralImage> squares_;
    std::vector<ComplexBuffer> spectra_;
    fftwf_plan forward_ = nullptr;
    fftwf_plan inverse_ = nullptr;
    fftwf_plan templateRows_ = nullptr;
    fftwf_plan templateColumns_ = nullptr;
};

}  // namespace vpe::quilt::search
