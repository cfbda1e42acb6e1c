// SPDX-License-Identifier: MIT
// RTI basis fitting on all threads.
#include "vpe/fit/rti_band_fitter.h"

#include <cmath>
#include <vector>

#include "vpe/common/parallel_for.h"

namespace vpe::fit {

RtiBandFitter::RtiBandFitter(const capture::Capture& capture, const model::RtiBasis& basis,
                             const capture::TransferFunction& stored, unsigned threads)
    : basis_(basis), stored_(stored), threads_(threads) {
    const auto images = static_cast<Eigen::Index>(capture.images.size());
    design_.resize(images, basis_.terms);
    std::vector<double> row(static_cast<std::size_t>(basis_.terms));
    for (Eigen::Index s = 0; s < images; ++s) {
        basis_.evaluate(capture.images[static_cast<std::size_t>(s)].light, row.data());
        for (int k = 0; k < basis_.terms; ++k) {
            design_(s, k) = row[static_cast<std::size_t>(k)];
        }
    }
    // The minimum-norm least-squares solution, without a ridge: HSH's normal equations are
    // badly conditioned when the lights leave part of the hemisphere empty, and any ridge
    // would change what the classic basis predicts there.
    pseudoInverse_ = design_.completeOrthogonalDecomposition().pseudoInverse();
}

void RtiBandFitter::fit(const capture::SampleBand& band, model::ModelRows& rows) const {
    const int terms = basis_.terms;
    const int images = band.images;
    rows.resize(band.width, band.rows, terms, false);
    common::parallelFor(
        static_cast<std::size_t>(band.rows), 1, threads_, [&](std::size_t begin, std::size_t end) {
            Eigen::MatrixXd values(images, 3);
            Eigen::VectorXd weights(images);
            for (std::size_t r = begin; r < end; ++r) {
                const int row = static_cast<int>(r);
                for (int x = 0; x < band.width; ++x) {
                    int usable = 0;
                    for (int s = 0; s < images; ++s) {
                        weights(s) = band.weight(s, row, x) > 0 ? 1.0 : 0.0;
                        usable += weights(s) > 0 ? 1 : 0;
                        for (int c = 0; c < 3; ++c) {
                            values(s, c) = stored_.encode(band.value(s, c, row, x));
                        }
                    }
                    const std::size_t p = rows.pixel(row, x);
                    if (usable < terms) {
                        continue;  // coefficients and RMS stay zero, the pixel invalid
                    }
                    Eigen::MatrixXd coefficients;
                    if (usable == images) {
                        coefficients = pseudoInverse_ * values;
                    } else {
                        const Eigen::MatrixXd weighted = weights.asDiagonal() * design_;
                        coefficients = weighted.completeOrthogonalDecomposition().solve(
                            weights.asDiagonal() * values);
                    }
                    const Eigen::MatrixXd residual =
                        weights.asDiagonal() * (design_ * coefficients - values);
                    rows.valid[p] = 1;
                    for (int c = 0; c < 3; ++c) {
                        for (int k = 0; k < terms; ++k) {
                            rows.coefficient[(p * 3 + c) * terms + k] =
                                static_cast<float>(coefficients(k, c));
                        }
                        rows.rms[p * 3 + c] =
                            static_cast<float>(std::sqrt(residual.col(c).squaredNorm() / usable));
                    }
                }
            }
        });
}

}  // namespace vpe::fit
