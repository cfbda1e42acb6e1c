// SPDX-License-Identifier: MIT
// Building a region's search structures: bounds, valid positions, principal components and
// spectra.
#include "region_search.h"

#include <algorithm>
#include <mutex>

#include "vpe/common/fftw_planner.h"
#include "vpe/common/input_error.h"
#include "vpe/common/principal_axes.h"

namespace vpe::quilt::search {

namespace {

// The smallest size ≥ n with no prime factor above 7: FFTW is fast on those.
int fftFriendly(int n) {
    for (int m = std::max(n, 1);; ++m) {
        int r = m;
        for (int p : {2, 3, 5, 7}) {
            while (r % p == 0) {
                r /= p;
            }
        }
        if (r == 1) {
            return m;
        }
    }
}

}  // namespace

RegionSearch::RegionSearch(const model::CoefficientImage& source,
                           const std::vector<std::uint8_t>& labels, int region, int block,
                           const QuiltSettings& settings, std::size_t enough)
    : source_(source), block_(block) {
    findBounds(labels, region);
    findCandidates(labels, region);
    if (candidateCount_ == 0 || candidateCount_ < enough) {
        return;
    }
    useFft_ = settings.search == QuiltSettings::Search::kFft;
    if (useFft_) {
        buildProjection(labels, region, settings);
        buildSpectra();
    }
}

RegionSearch::~RegionSearch() {
    std::lock_guard lock(common::fftwPlannerMutex());
    if (forward_) {
        fftwf_destroy_plan(forward_);
    }
    if (inverse_) {
        fftwf_destroy_plan(inverse_);
    }
    if (templateRows_) {
        fftwf_destroy_plan(templateRows_);
    }
    if (templateColumns_) {
        fftwf_destroy_plan(templateColumns_);
    }
}

void RegionSearch::findBounds(const std::vector<std::uint8_t>& labels, int region) {
    int x0 = source_.width, y0 = source_.height, x1 = -1, y1 = -1;
    for (int y = 0; y < source_.height; ++y) {
        for (int x = 0; x < source_.width; ++x) {
            if (labels[static_cast<std::size_t>(y) * source_.width + x] == region) {
                x0 = std::min(x0, x);
                y0 = std::min(y0, y);
                x1 = std::max(x1, x);
                y1 = std::max(y1, y);
            }
        }
    }
    bx_ = x0;
    by_ = y0;
    bw_ = std::max(0, x1 - x0 + 1);
    bh_ = std::max(0, y1 - y0 + 1);
}

void RegionSearch::findCandidates(const std::vector<std::uint8_t>& labels, int region) {
    if (bw_ < block_ || bh_ < block_) {
        return;
    }
    std::vector<double> inside(static_cast<std::size_t>(bw_) * bh_);
    for (int y = 0; y < bh_; ++y) {
        for (int x = 0; x < bw_; ++x) {
            inside[static_cast<std::size_t>(y) * bw_ + x] =
                labels[static_cast<std::size_t>(y + by_) * source_.width + x + bx_] == region;
        }
    }
    IntegralImage count(bw_, bh_);
    count.build(inside, bh_);
    valid_.assign(static_cast<std::size_t>(positionsX()) * positionsY(), 0);
    const double full = static_cast<double>(block_) * block_;
    for (int py = 0; py < positionsY(); ++py) {
        for (int px = 0; px < positionsX(); ++px) {
            if (count.sum(px, py, px + block_, py + block_) >= full - 0.5) {
                valid_[static_cast<std::size_t>(py) * positionsX() + px] = 1;
                candidateList_.push_back(static_cast<std::uint32_t>(py * positionsX() + px));
                ++candidateCount_;
            }
        }
    }
}

// Principal components of the region's coefficient vectors: the search runs on the few
// that hold most of the variance (SSD of differences is unchanged by centring).
void RegionSearch::buildProjection(const std::vector<std::uint8_t>& labels, int region,
                                   const QuiltSettings& settings) {
    const int c = source_.dims;
    std::vector<const float*> texels;
    for (int y = by_; y < by_ + bh_; ++y) {
        for (int x = bx_; x < bx_ + bw_; ++x) {
            if (labels[static_cast<std::size_t>(y) * source_.width + x] == region) {
                texels.push_back(source_.at(x, y));
            }
        }
    }
    const common::PrincipalAxes axes = common::principalAxes(
        texels.size(), c, [&](std::size_t i) { return texels[i]; },
        common::AxisSelection{.maxAxes = std::min(settings.maxComponents, c),
                              .varianceToKeep = settings.pcaVariance});
    components_ = axes.count();
    const Eigen::MatrixXd& basis = axes.axes;
    const Eigen::VectorXd& mean = axes.mean;
    projected_.assign(static_cast<std::size_t>(bw_) * bh_ * components_, 0.0f);
    std::vector<double> squares(static_cast<std::size_t>(bw_) * bh_, 0.0);
    for (int y = 0; y < bh_; ++y) {
        for (int x = 0; x < bw_; ++x) {
            if (labels[static_cast<std::size_t>(y + by_) * source_.width + x + bx_] != region) {
                continue;  // never inside a valid block: left at zero
            }
            const Eigen::VectorXd d =
                Eigen::Map<const Eigen::VectorXf>(source_.at(x + bx_, y + by_), c).cast<double>() -
                mean;
            const Eigen::VectorXd p = basis.transpose() * d;
            float* out = &projected_[(static_cast<std::size_t>(y) * bw_ + x) * components_];
            double s = 0;
            for (int k = 0; k < components_; ++k) {
                out[k] = static_cast<float>(p[k]);
                s += static_cast<double>(out[k]) * static_cast<double>(out[k]);
            }
            squares[static_cast<std::size_t>(y) * bw_ + x] = s;
        }
    }
    squares_ = std::make_unique<IntegralImage>(bw_, bh_);
    squares_->build(squares, bh_);
}

// FFTs of the region's PCA components, padded to an FFT-friendly size. Cyclic correlation
// is exact for every valid block: a candidate corner plus a block offset stays inside.
void RegionSearch::buildSpectra() {
    fw_ = fftFriendly(bw_);
    fh_ = fftFriendly(bh_);
    RealBuffer image = allocateReal(static_cast<std::size_t>(fw_) * fh_);
    ComplexBuffer scratch = allocateComplex(spectrumSize());
    ComplexBuffer rows = allocateComplex(spectrumSize());
    const int spectrumWidth = fw_ / 2 + 1;
    {
        // FFTW_ESTIMATE: measured plans could differ from run to run, and with them the
        // rounding of the approximate errors: a quilt must not.
        std::lock_guard lock(common::fftwPlannerMutex());
        forward_ = fftwf_plan_dft_r2c_2d(fh_, fw_, image.get(), scratch.get(), FFTW_ESTIMATE);
        inverse_ = fftwf_plan_dft_c2r_2d(fh_, fw_, scratch.get(), image.get(), FFTW_ESTIMATE);
        templateRows_ =
            fftwf_plan_many_dft_r2c(1, &fw_, block_, image.get(), nullptr, 1, fw_, rows.get(),
                                    nullptr, 1, spectrumWidth, FFTW_ESTIMATE);
        templateColumns_ = fftwf_plan_many_dft(
            1, &fh_, spectrumWidth, rows.get(), nullptr, spectrumWidth, 1, scratch.get(), nullptr,
            spectrumWidth, 1, FFTW_FORWARD, FFTW_ESTIMATE | FFTW_PRESERVE_INPUT);
    }
    for (int k = 0; k < components_; ++k) {
        std::fill(image.get(), image.get() + static_cast<std::size_t>(fw_) * fh_, 0.0f);
        for (int y = 0; y < bh_; ++y) {
            for (int x = 0; x < bw_; ++x) {
                image.get()[static_cast<std::size_t>(y) * fw_ + x] =
                    projected_[(static_cast<std::size_t>(y) * bw_ + x) * components_ + k];
            }
        }
        spectra_.push_back(allocateComplex(spectrumSize()));
        fftwf_execute_dft_r2c(forward_, image.get(), spectra_.back().get());
    }
}

}  // namespace vpe::quilt::search
