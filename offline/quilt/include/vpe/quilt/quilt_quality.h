// SPDX-License-Identifier: MIT
// How good a quilting result is, per region, from what `vpe quilt` wrote: does it copy only
// from its region, does it reproduce the region's distribution of coefficient vectors and its
// spatial frequencies, are its seams as smooth as its block interiors, and how large is the
// largest verbatim copy. Definitions, with their reference values, in docs/quilt-quality.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/model/coefficient_image.h"
#include "vpe/quilt/quilt_folder.h"

namespace vpe::quilt {

struct SlicedWassersteinOptions {
    int directions = 64;
    std::uint64_t seed = 1;
    // Larger sets are subsampled (evenly, in their order) to keep 64 sorts cheap.
    std::size_t maxSamples = 65536;
    unsigned threads = 1;
};

// Sliced 2-Wasserstein distance between two sets of `dims`-vectors: √(mean over random unit
// directions θ of W₂²(θ·A, θ·B)), the 1-D distances exact for sets of any two sizes.
// Identical multisets give exactly 0. Deterministic for a seed.
double slicedWasserstein(const float* a, std::size_t countA, const float* b, std::size_t countB,
                         int dims, const SlicedWassersteinOptions& options);

struct QualityOptions {
    SlicedWassersteinOptions wasserstein;
    int spectrumComponents = 4;  // leading PCA components of the source region
    int maxSpectrumWindow = 256;
    int maxSpectrumTiles = 16;  // output windows compared with the source's
    unsigned threads = 1;
};

// Every figure is NaN when undefined (no pairs, no positions, a region too thin).
struct RegionQuality {
    int region = 0;
    std::size_t outputPixels = 0;
    std::size_t positionedPixels = 0;  // output pixels positions.exr gives a source for
    std::size_t sourcePixels = 0;      // valid source pixels labelled with the region

    // Region correctness: share of positioned pixels whose source has the region's label.
    std::size_t correctPixels = 0;
    double correctness = 0;
    // Largest |output − source at its position| over all coefficients: 0 for a quilter that
    // copies, as Image Quilting with a minimum-error cut does.
    double copyMaxDifference = 0;

    // Sliced Wasserstein: output vs the source region, and between the region's top and
    // bottom halves (in raster order) as the scale of "as close as the source to itself".
    double wasserstein = 0;
    double wassersteinSelf = 0;
    double wassersteinRatio = 0;

    // Radially averaged power spectra of the leading PCA components: mean |log ratio| over
    // frequency bins between output windows and the two source windows (the halves of the
    // largest square inside the region), and between those two source windows.
    double spectrum = 0;
    double spectrumSelf = 0;
    double spectrumRatio = 0;
    int spectrumWindowWidth = 0;
    int spectrumWindowHeight = 0;
    int spectrumComponents = 0;
    int spectrumTiles = 0;

    // Seams: mean squared coefficient difference (per coefficient) of 4-neighbour output
    // pairs whose sources are not neighbours in the same direction, over the same for pairs
    // whose sources are (block interiors). Without interior pairs in the output the interior
    // figure comes from the source region's own neighbour pairs.
    std::size_t seamPairs = 0;
    std::size_t interiorPairs = 0;
    double seamMsd = 0;
    double interiorMsd = 0;
    double seamRatio = 0;
    bool interiorFromSource = false;

    // The largest 4-connected set of output pixels with one source offset (source − output).
    std::size_t largestCopy = 0;
    double largestCopyFraction = 0;
    int largestCopyOffsetX = 0;
    int largestCopyOffsetY = 0;
};

// `output` is region map `region` (the quilt), `positions` its copy positions; `source` and
// `labels` the model that was quilted and its region labels.
RegionQuality measureRegionQuality(const model::CoefficientImage& source,
                                   const std::vector<std::uint8_t>& labels, int region,
                                   const model::CoefficientImage& output,
                                   const PositionMap& positions, const QualityOptions& options);

}  // namespace vpe::quilt
