// SPDX-License-Identifier: MIT
// Region-restricted Image Quilting with FFT overlap search.
#include "vpe/quilt/image_quilter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <tuple>

#include <Eigen/Dense>
#include <fftw3.h>

#include "vpe/common/fftw_planner.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/principal_axes.h"
#include "vpe/common/random_bits.h"

#include "region_search.h"

namespace vpe::quilt {

namespace {

using search::allocateComplex;
using search::allocateReal;
using search::ComplexBuffer;
using search::OverlapShape;
using search::RealBuffer;
using search::RegionSearch;

constexpr int kDistanceLanes = 16;

// Σ (a − b)² over n channels into sixteen float lanes (one AVX-512 vector, two AVX2, four
// SSE), lane l holding channels l, l + 16, …. Inlined into each instruction-set clone below.
// The file is compiled without FMA contraction and the lanes are fixed, so every clone
// returns the same bits: a quilt does not depend on the machine.
[[gnu::always_inline]] inline void laneSquares(const float* a, const float* b, int n,
                                               float (&lanes)[kDistanceLanes]) {
    int i = 0;
    for (; i + kDistanceLanes <= n; i += kDistanceLanes) {
        for (int l = 0; l < kDistanceLanes; ++l) {
            const float d = a[i + l] - b[i + l];
            lanes[l] += d * d;
        }
    }
    for (int l = 0; i < n; ++i, ++l) {
        const float d = a[i] - b[i];
        lanes[l] += d * d;
    }
}

// Σ (a − b)² over n channels, the lanes summed in double. Scoring candidates on all 66
// channels one double at a time took over a quarter of the quilting.
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) double
squaredDistance(const float* a, const float* b, int n) {
    float lanes[kDistanceLanes] = {};
    laneSquares(a, b, n, lanes);
    double sum = 0;
    for (int l = 0; l < kDistanceLanes; ++l) {
        sum += static_cast<double>(lanes[l]);
    }
    return sum;
}

// The overlap error of one candidate: Σ over the overlap's pixels i of Σ (a_i − b_i)², with
// a_i = placed[i] and b_i = candidate + offsets[i]. Per pixel in sixteen float lanes (as
// squaredDistance), added to sixteen double lanes, summed once at the end: one call per
// candidate instead of one per pixel, and no per-pixel reduction.
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) double overlapError(
    const float* const* placed, const std::ptrdiff_t* offsets, std::size_t pixels,
    const float* candidate, int n) {
    double sums[kDistanceLanes] = {};
    for (std::size_t p = 0; p < pixels; ++p) {
        float lanes[kDistanceLanes] = {};
        laneSquares(placed[p], candidate + offsets[p], n, lanes);
        for (int l = 0; l < kDistanceLanes; ++l) {
            sums[l] += static_cast<double>(lanes[l]);
        }
    }
    double sum = 0;
    for (int l = 0; l < kDistanceLanes; ++l) {
        sum += sums[l];
    }
    return sum;
}

// acc += Ŝ · conj(T̂), element by element (each element's arithmetic is the same whatever the
// vector width, so the clones agree bit for bit).
__attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"))) void
accumulateCrossSpectrum(fftwf_complex* __restrict acc, const fftwf_complex* __restrict s,
                        const fftwf_complex* __restrict t, std::size_t n) {
    for (std::size_t f = 0; f < n; ++f) {
        acc[f][0] += s[f][0] * t[f][0] + s[f][1] * t[f][1];
        acc[f][1] += s[f][1] * t[f][0] - s[f][0] * t[f][1];
    }
}

// Per-thread scratch for the FFT search.
struct SearchScratch {
    RealBuffer image;
    ComplexBuffer rows;  // the template's row transforms; rows past the block stay zero
    ComplexBuffer templateSpectrum;
    ComplexBuffer accumulated;
    explicit SearchScratch(const RegionSearch& search)
        : image(allocateReal(static_cast<std::size_t>(search.fftWidth()) * search.fftHeight())),
          rows(allocateComplex(search.spectrumSize())),
          templateSpectrum(allocateComplex(search.spectrumSize())),
          accumulated(allocateComplex(search.spectrumSize())) {
        std::fill(&rows.get()[0][0], &rows.get()[0][0] + 2 * search.spectrumSize(), 0.0f);
    }
};

struct Candidate {
    double error;
    int px, py;  // bounding-box coordinates
    bool operator<(const Candidate& other) const {
        return error < other.error ||
               (error == other.error && (py < other.py || (py == other.py && px < other.px)));
    }
};

// Where the blocks of a row go: every block starts at origins[i] and is `block` wide.
// Without wrapping, origins step by block − overlap and the canvas is cropped to the output;
// wrapping, the canvas is exactly the output's width and the origins spread over it so that
// the last block overlaps the first across x = width | 0 (steps differ by at most a pixel,
// so each left overlap is within a pixel of the others).
struct ColumnLayout {
    std::vector<int> origins;
    int canvasWidth = 0;
    bool wrap = false;
};

// A wrapping row of n blocks over `width` pixels, or nothing when its overlaps would leave
// the range [1, (block − 1) / 2] in which the boundary cuts work.
std::optional<ColumnLayout> wrappingColumns(int width, int block, int n) {
    if (n < 2) {
        return std::nullopt;
    }
    ColumnLayout layout;
    layout.wrap = true;
    layout.canvasWidth = width;
    for (int i = 0; i < n; ++i) {
        layout.origins.push_back(static_cast<int>(static_cast<long long>(i) * width / n));
    }
    for (int i = 0; i < n; ++i) {
        const int next = i + 1 < n ? layout.origins[static_cast<std::size_t>(i) + 1] : width;
        const int overlap = layout.origins[static_cast<std::size_t>(i)] + block - next;
        if (overlap < 1 || overlap > (block - 1) / 2) {
            return std::nullopt;
        }
    }
    return layout;
}

ColumnLayout columnLayout(int width, int block, int overlap, bool wrap) {
    const int step = block - overlap;
    if (wrap) {
        // As many blocks as the nominal step needs (overlaps a little wider than asked), else
        // one fewer (a little narrower).
        const int atLeast = (width + step - 1) / step;
        for (int n : {atLeast, atLeast - 1}) {
            if (std::optional<ColumnLayout> layout = wrappingColumns(width, block, n)) {
                return *layout;
            }
        }
        // Two blocks a row, each overlapping the other on both sides by at most (block − 1) / 2.
        const int least = 2 * (block - (block - 1) / 2);
        throw common::InputError("a texture that wraps in u cannot be " + std::to_string(width) +
                                 " pixels wide with " + std::to_string(block) +
                                 "-pixel blocks overlapping by " + std::to_string(overlap) +
                                 " (at least " + std::to_string(least) + ")");
    }
    ColumnLayout layout;
    const int blocks = std::max(1, (width - overlap + step - 1) / step);
    for (int i = 0; i < blocks; ++i) {
        layout.origins.push_back(i * step);
    }
    layout.canvasWidth = blocks * step + overlap;
    return layout;
}

class Quilter {
public:
    Quilter(const model::CoefficientImage& source, const RegionSearch& search, int region,
            int width, int height, int block, int overlap, const QuiltSettings& settings)
        : source_(source),
          search_(search),
          region_(region),
          block_(block),
          overlap_(overlap),
          step_(block - overlap),
          settings_(settings),
          columns_(columnLayout(width, block, overlap, settings.wrapU)) {
        blocksX_ = static_cast<int>(columns_.origins.size());
        blocksY_ = std::max(1, (height - overlap + step_ - 1) / step_);
        canvasWidth_ = columns_.canvasWidth;
        canvasHeight_ = blocksY_ * step_ + overlap;
        // Skewed wavefronts d = i + skew·j: a block depends on its left, top and top-right
        // neighbours (the last overlaps its top-right corner), all on earlier fronts, and
        // blocks of one front are at least two steps apart, so they never touch. Wrapping,
        // the last block of row j also touches the first of row j + 1 (on front skew·(j + 1)
        // versus n − 1 + skew·j): with three blocks a row, a skew of 2 would put them on one
        // front, so it is 3. Which of the two comes first does not matter, only that they do
        // not run at once: each block's overlap is what is placed when it is placed.
        skew_ = columns_.wrap && blocksX_ == 3 ? 3 : 2;
        sourceX_.assign(static_cast<std::size_t>(canvasWidth_) * canvasHeight_, -1);
        sourceY_.assign(sourceX_.size(), -1);
        if (search_.usesFft()) {
            buildOverlapEnergies();
        }
    }

    void run() {
        const int fronts = blocksX_ + skew_ * blocksY_;
        for (int d = 0; d < fronts; ++d) {
            std::vector<std::pair<int, int>> front;
            for (int j = 0; j < blocksY_; ++j) {
                const int i = d - skew_ * j;
                if (i >= 0 && i < blocksX_) {
                    front.emplace_back(i, j);
                }
            }
            common::parallelFor(front.size(), 1, settings_.threads,
                                [&](std::size_t begin, std::size_t end) {
                                    std::unique_ptr<SearchScratch> scratch = acquireScratch();
                                    for (std::size_t f = begin; f < end; ++f) {
                                        placeBlock(front[f].first, front[f].second, scratch.get());
                                    }
                                    releaseScratch(std::move(scratch));
                                });
        }
    }

    RegionQuilt result(int width, int height) const {
        RegionQuilt out;
        out.width = width;
        out.height = height;
        out.sourceX.resize(static_cast<std::size_t>(width) * height);
        out.sourceY.resize(out.sourceX.size());
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                out.sourceX[static_cast<std::size_t>(y) * width + x] = sourceX_[index(x, y)];
                out.sourceY[static_cast<std::size_t>(y) * width + x] = sourceY_[index(x, y)];
            }
        }
        out.block = block_;
        out.overlap = overlap_;
        out.components = search_.components();
        out.candidates = search_.candidateCount();
        out.blocks = blocksX_ * blocksY_;
        out.wrapU = columns_.wrap;
        return out;
    }

private:
    // Canvas pixel (x, y); wrapping, x may run past the right edge (a block's right part
    // continues at the left), never by more than a block.
    std::size_t index(int x, int y) const {
        if (x >= canvasWidth_) {
            x -= canvasWidth_;
        }
        return static_cast<std::size_t>(y) * canvasWidth_ + x;
    }

    // The overlap of block (i, j) with what is placed before it.
    OverlapShape shapeOf(int i, int j) const {
        OverlapShape shape;
        const auto origin = [this](int k) { return columns_.origins[static_cast<std::size_t>(k)]; };
        if (i > 0) {
            shape.left = origin(i - 1) + block_ - origin(i);
        }
        if (j > 0) {
            shape.top = overlap_;
        }
        if (columns_.wrap && i == blocksX_ - 1) {
            shape.right = origin(i) + block_ - canvasWidth_;
        }
        return shape;
    }

    // FFT scratch (a few MiB) is kept between wavefronts: each front runs on fresh threads,
    // and allocating, clearing and faulting in new buffers for every front showed in the
    // profile.
    std::unique_ptr<SearchScratch> acquireScratch() {
        if (!search_.usesFft()) {
            return nullptr;
        }
        {
            std::lock_guard lock(scratchMutex_);
            if (!freeScratch_.empty()) {
                std::unique_ptr<SearchScratch> scratch = std::move(freeScratch_.back());
                freeScratch_.pop_back();
                return scratch;
            }
        }
        return std::make_unique<SearchScratch>(search_);
    }
    void releaseScratch(std::unique_ptr<SearchScratch> scratch) {
        if (scratch) {
            std::lock_guard lock(scratchMutex_);
            freeScratch_.push_back(std::move(scratch));
        }
    }

    // Σ S² over the overlap at every candidate, for every overlap shape the blocks have (left,
    // top, both; wrapping, also the left widths a pixel apart and the last column's right
    // strip), computed once instead of up to twenty summed-area lookups per candidate and block.
    void buildOverlapEnergies() {
        const int nx = search_.positionsX(), ny = search_.positionsY();
        for (int j = 0; j < std::min(blocksY_, 2); ++j) {  // rows past the second repeat it
            for (int i = 0; i < blocksX_; ++i) {
                const OverlapShape shape = shapeOf(i, j);
                if (!shape.any() || overlapEnergies_.count(shape.key()) != 0) {
                    continue;
                }
                std::vector<double>& energy = overlapEnergies_[shape.key()];
                energy.assign(static_cast<std::size_t>(nx) * ny, 0.0);
                for (int py = 0; py < ny; ++py) {
                    for (int px = 0; px < nx; ++px) {
                        if (search_.valid(px, py)) {
                            energy[static_cast<std::size_t>(py) * nx + px] =
                                search_.overlapEnergy(px, py, shape);
                        }
                    }
                }
            }
        }
    }

    void placeBlock(int i, int j, SearchScratch* scratch) {
        const int ox = columns_.origins[static_cast<std::size_t>(i)], oy = j * step_;
        const OverlapShape shape = shapeOf(i, j);
        std::uint64_t rng = common::mixBits(
            settings_.seed ^ common::mixBits(static_cast<std::uint64_t>(region_) * 0x9e37 +
                                             static_cast<std::uint64_t>(j) * 0x10000 +
                                             static_cast<std::uint64_t>(i)));
        auto random = [&rng](std::size_t n) {
            rng = common::mixBits(rng);
            return static_cast<std::size_t>(common::uniformFromBits(rng) * static_cast<double>(n)) %
                   n;
        };
        int px, py;
        if (!shape.any()) {
            std::tie(px, py) = search_.candidate(random(search_.candidateCount()));
        } else {
            std::vector<Candidate> shortlist =
                search_.usesFft() ? fftShortlist(ox, oy, shape, *scratch) : allCandidates();
            // Exact errors on all channels, then a random pick within (1 + ε) of the best.
            const OverlapPixels overlap = overlapPixels(ox, oy, shape);
            for (Candidate& c : shortlist) {
                c.error = overlapError(
                    overlap.placed.data(), overlap.offsets.data(), overlap.placed.size(),
                    source_.at(search_.boundsX() + c.px, search_.boundsY() + c.py), source_.dims);
            }
            std::sort(shortlist.begin(), shortlist.end());
            if (shortlist.empty()) {
                throw std::logic_error(
                    "quilting: a region with candidates gave an empty shortlist");
            }
            const double limit = shortlist.front().error * (1.0 + settings_.tolerance) + 1e-12;
            std::size_t within = 0;
            while (within < shortlist.size() && shortlist[within].error <= limit) {
                ++within;
            }
            const Candidate& chosen = shortlist[random(within)];
            px = chosen.px;
            py = chosen.py;
        }
        paste(ox, oy, px, py, shape);
    }

    // The coefficient vector currently at output pixel (x, y).
    const float* placed(int x, int y) const {
        const std::size_t at = index(x, y);
        return source_.at(sourceX_[at], sourceY_[at]);
    }

    // The overlap's pixels of the block at (ox, oy): what is placed there, and where each
    // sits in a candidate block (source offset from the candidate's corner).
    struct OverlapPixels {
        std::vector<const float*> placed;
        std::vector<std::ptrdiff_t> offsets;
    };
    OverlapPixels overlapPixels(int ox, int oy, const OverlapShape& shape) const {
        OverlapPixels pixels;
        for (int qy = 0; qy < block_; ++qy) {
            for (int qx = 0; qx < block_; ++qx) {
                if (shape.contains(qx, qy, block_)) {
                    pixels.placed.push_back(placed(ox + qx, oy + qy));
                    pixels.offsets.push_back(
                        (static_cast<std::ptrdiff_t>(qy) * source_.width + qx) * source_.dims);
                }
            }
        }
        return pixels;
    }

    std::vector<Candidate> allCandidates() const {
        std::vector<Candidate> all;
        all.reserve(search_.candidateList().size());
        const int nx = search_.positionsX();
        for (const std::uint32_t at : search_.candidateList()) {
            all.push_back({0.0, static_cast<int>(at) % nx, static_cast<int>(at) / nx});
        }
        return all;
    }

    // Overlap SSD of every candidate on the PCA components: Σ S² − 2 Σ S·T + Σ T², the cross
    // term for all positions at once as Σ_k IFFT(Ŝ_k · conj(T̂_k)) — one inverse transform.
    std::vector<Candidate> fftShortlist(int ox, int oy, const OverlapShape& shape,
                                        SearchScratch& scratch) const {
        const int fw = search_.fftWidth(), fh = search_.fftHeight();
        const int p = search_.components();
        const std::size_t spectrum = search_.spectrumSize();
        float* image = scratch.image.get();
        fftwf_complex* t = scratch.templateSpectrum.get();
        fftwf_complex* acc = scratch.accumulated.get();
        std::fill(&acc[0][0], &acc[0][0] + 2 * spectrum, 0.0f);
        double templateEnergy = 0;
        for (int k = 0; k < p; ++k) {
            std::fill(image, image + static_cast<std::size_t>(fw) * block_, 0.0f);
            for (int qy = 0; qy < block_; ++qy) {
                for (int qx = 0; qx < block_; ++qx) {
                    if (!shape.contains(qx, qy, block_)) {
                        continue;
                    }
                    const std::size_t at = index(ox + qx, oy + qy);
                    const float v = search_.projected(sourceX_[at], sourceY_[at])[k];
                    image[static_cast<std::size_t>(qy) * fw + qx] = v;
                    templateEnergy += static_cast<double>(v) * static_cast<double>(v);
                }
            }
            fftwf_execute_dft_r2c(search_.templateRows(), image, scratch.rows.get());
            fftwf_execute_dft(search_.templateColumns(), scratch.rows.get(), t);
            accumulateCrossSpectrum(acc, search_.spectrum(k), t, spectrum);
        }
        fftwf_execute_dft_c2r(search_.inverse(), acc, image);
        const double scale = 1.0 / (static_cast<double>(fw) * fh);  // FFTW is unnormalized
        // Keep the `shortlist` smallest approximate errors.
        std::vector<Candidate> best;
        best.reserve(static_cast<std::size_t>(settings_.shortlist) + 1);
        const int nx = search_.positionsX();
        const std::vector<double>& energy = overlapEnergies_.at(shape.key());
        // Only the valid positions, in row order (a thin region's are a small part of its
        // bounding box).
        for (const std::uint32_t at : search_.candidateList()) {
            const int px = static_cast<int>(at) % nx, py = static_cast<int>(at) / nx;
            const double cross =
                static_cast<double>(image[static_cast<std::size_t>(py) * fw + px]) * scale;
            const Candidate c{energy[at] - 2.0 * cross + templateEnergy, px, py};
            if (static_cast<int>(best.size()) < settings_.shortlist) {
                best.push_back(c);
                std::push_heap(best.begin(), best.end());
            } else if (c < best.front()) {
                std::pop_heap(best.begin(), best.end());
                best.back() = c;
                std::push_heap(best.begin(), best.end());
            }
        }
        return best;
    }

    // Minimum-error boundary cuts through the overlap (dynamic programming), then copy the
    // block's positions on the new side.
    void paste(int ox, int oy, int px, int py, const OverlapShape& shape) {
        const int sx = search_.boundsX() + px, sy = search_.boundsY() + py;
        const int c = source_.dims;
        auto error = [&](int qx, int qy) {
            return squaredDistance(placed(ox + qx, oy + qy), source_.at(sx + qx, sy + qy), c);
        };
        std::vector<int> cutX(static_cast<std::size_t>(block_), 0),
            cutY(static_cast<std::size_t>(block_), 0),
            cutRight(static_cast<std::size_t>(block_), 0);
        if (shape.left > 0) {
            cutX = minimumCut(block_, shape.left,
                              [&](int along, int across) { return error(across, along); });
        }
        if (shape.top > 0) {
            cutY = minimumCut(block_, shape.top,
                              [&](int along, int across) { return error(along, across); });
        }
        // The seam: the last block of a wrapping row meets the first one through a cut too,
        // the new side on its left.
        const int rightStrip = block_ - shape.right;
        if (shape.right > 0) {
            cutRight = minimumCut(block_, shape.right, [&](int along, int across) {
                return error(rightStrip + across, along);
            });
        }
        for (int qy = 0; qy < block_; ++qy) {
            for (int qx = 0; qx < block_; ++qx) {
                const bool newLeft = shape.left == 0 || qx >= cutX[static_cast<std::size_t>(qy)];
                const bool newTop = shape.top == 0 || qy >= cutY[static_cast<std::size_t>(qx)];
                const bool newRight =
                    shape.right == 0 || qx - rightStrip <= cutRight[static_cast<std::size_t>(qy)];
                if (newLeft && newTop && newRight) {
                    const std::size_t at = index(ox + qx, oy + qy);
                    sourceX_[at] = sx + qx;
                    sourceY_[at] = sy + qy;
                }
            }
        }
    }

    // The cheapest path along a strip `length` long and `width` wide (moving at most one
    // step across per step along); returns, per position along, where the new side starts.
    template <typename Error>
    static std::vector<int> minimumCut(int length, int width, Error error) {
        std::vector<double> cost(static_cast<std::size_t>(length) * width);
        for (int a = 0; a < length; ++a) {
            for (int b = 0; b < width; ++b) {
                double previous = 0;
                if (a > 0) {
                    previous = std::numeric_limits<double>::infinity();
                    for (int db = -1; db <= 1; ++db) {
                        if (b + db >= 0 && b + db < width) {
                            previous = std::min(
                                previous, cost[static_cast<std::size_t>(a - 1) * width + b + db]);
                        }
                    }
                }
                cost[static_cast<std::size_t>(a) * width + b] = error(a, b) + previous;
            }
        }
        std::vector<int> cut(static_cast<std::size_t>(length));
        int b = static_cast<int>(std::min_element(cost.end() - width, cost.end()) -
                                 (cost.end() - width));
        for (int a = length - 1; a >= 0; --a) {
            cut[static_cast<std::size_t>(a)] = b;
            if (a > 0) {
                int bestB = b;
                double bestCost = std::numeric_limits<double>::infinity();
                for (int db = -1; db <= 1; ++db) {
                    const int nb = b + db;
                    if (nb >= 0 && nb < width &&
                        cost[static_cast<std::size_t>(a - 1) * width + nb] < bestCost) {
                        bestCost = cost[static_cast<std::size_t>(a - 1) * width + nb];
                        bestB = nb;
                    }
                }
                b = bestB;
            }
        }
        return cut;
    }

    const model::CoefficientImage& source_;
    const RegionSearch& search_;
    int region_, block_, overlap_, step_;
    QuiltSettings settings_;
    ColumnLayout columns_;
    int skew_ = 2;
    int blocksX_ = 0, blocksY_ = 0, canvasWidth_ = 0, canvasHeight_ = 0;
    std::vector<std::int32_t> sourceX_, sourceY_;
    // [shape.key()][py * positionsX + px]; built before run(), only read while it runs.
    std::map<std::tuple<int, int, int>, std::vector<double>> overlapEnergies_;
    std::mutex scratchMutex_;
    std::vector<std::unique_ptr<SearchScratch>> freeScratch_;
};

}  // namespace

RegionQuilt quiltRegion(const model::CoefficientImage& source,
                        const std::vector<std::uint8_t>& labels, int region, int width, int height,
                        const QuiltSettings& settings) {
    if (width <= 0 || height <= 0) {
        throw common::InputError("output size must be positive");
    }
    if (settings.block < 8 || settings.overlap < 1 || 2 * settings.overlap >= settings.block) {
        throw common::InputError("--block must be at least 8 and --overlap between 1 and block/2");
    }
    // A thin region may not hold the requested block, or hold so few that the texture would
    // repeat them: shrink the block (overlap in proportion) until there is a real choice.
    constexpr std::size_t kEnoughCandidates = 256;
    for (int block = settings.block; block >= 8; block = block * 3 / 4) {
        // Keep at least three pixels of overlap: with two, the boundary cut has too little room and
        // the seams show as lines (seen on the synthetic streaks). Less than half a block.
        const int overlap = std::clamp(settings.overlap * block / settings.block,
                                       std::min(3, settings.overlap), (block - 1) / 2);
        const bool smallest = block * 3 / 4 < 8;
        const RegionSearch search(source, labels, region, block, settings,
                                  smallest ? 1 : kEnoughCandidates);
        if (search.candidateCount() == 0 ||
            (search.candidateCount() < kEnoughCandidates && !smallest)) {
            continue;
        }
        Quilter quilter(source, search, region, width, height, block, overlap, settings);
        quilter.run();
        return quilter.result(width, height);
    }
    throw common::InputError("region " + std::to_string(region) +
                             " is too small or too thin to hold an 8-pixel block");
}

}  // namespace vpe::quilt
