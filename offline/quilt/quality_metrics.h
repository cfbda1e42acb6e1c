// SPDX-License-Identifier: MIT
// The quilt-quality metrics, one unit each (private to quilt/): quilt_quality.cpp gathers the
// samples and calls them; sliced_wasserstein.cpp, quality_spectrum.cpp, quality_seams.cpp and
// quality_copies.cpp measure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "vpe/quilt/quilt_folder.h"
#include "vpe/quilt/quilt_quality.h"

namespace vpe::quilt::metrics {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Indices 0..count-1, or `limit` of them evenly spread when there are more.
std::vector<std::size_t> evenSubset(std::size_t count, std::size_t limit);

// Radially averaged power spectra of the output against the source's (spectrum, its self
// reference and their ratio), on the region's largest square.
void measureSpectrum(const model::CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                     const std::vector<float>& sourceSamples, const model::CoefficientImage& output,
                     const QualityOptions& options, RegionQuality& quality);

// Mean squared differences across the quilt's seams against its block interiors.
void measureSeams(const model::CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                  const model::CoefficientImage& output, const PositionMap& positions,
                  RegionQuality& quality);

// The largest area copied verbatim (one connected run of constant source offset).
void measureLargestCopy(const PositionMap& positions, RegionQuality& quality);

}  // namespace vpe::quilt::metrics
