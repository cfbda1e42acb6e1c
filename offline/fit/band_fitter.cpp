// SPDX-License-Identifier: MIT
// Band fitting on all threads.
#include "vpe/fit/band_fitter.h"

#include <algorithm>

#include "vpe/common/parallel_for.h"
#include "vpe/fit/chunk_setup.h"

namespace vpe::fit {

BandFitter::BandFitter(const capture::Capture& capture, const capture::SurfaceGeometry& geometry,
                       const normals::NormalMap& normals, const BandFitSettings& settings)
    : capture_(capture),
      geometry_(geometry),
      normals_(normals),
      settings_(settings),
      lights_(kernelLights(capture)),
      lightSet_(kernelLightSet(capture, lights_)) {
    if (settings_.extended) {
        lightTable_ = std::make_unique<ExtendedLightTable>(capture);
    }
}

void BandFitter::fit(const capture::SampleBand& band, model::ModelRows& rows) const {
    const int coefficients = proto::coefficientCount(settings_.fit.harmonics);
    const int chunksPerRow = (band.width + kLanes - 1) / kLanes;
    rows.resize(band.width, band.rows, coefficients, settings_.extended);
    common::parallelFor(
        static_cast<std::size_t>(band.rows) * chunksPerRow, 4, settings_.threads,
        [&](std::size_t begin, std::size_t end) {
            // Not value-initialized: the kernel clears the sums it uses and the solve writes
            // what is read; zeroing these 38 KiB for every four chunks added 2.5 GB of writes
            // to a 2048² fit.
            auto sums = std::make_unique_for_overwrite<NormalEquationSums>();
            auto plain = std::make_unique_for_overwrite<ChunkSolution>();
            auto withTransport = std::make_unique_for_overwrite<ExtendedChunkSolution>();
            const ChunkSolution& solution = settings_.extended ? withTransport->brdf : *plain;
            ChunkGeometry chunk;
            for (std::size_t index = begin; index < end; ++index) {
                const int r = static_cast<int>(index / chunksPerRow);
                const int x0 = static_cast<int>(index % chunksPerRow) * kLanes;
                bool laneValid[kLanes];
                fillChunkGeometry(geometry_, normals_, x0, band.rowBegin + r, chunk, laneValid);
                if (settings_.extended) {
                    fitChunkExtendedRefiningNormals(capture_, *lightTable_, chunk, laneValid,
                                                    lightSet_, band, r, x0, settings_.fit,
                                                    *withTransport);
                } else {
                    accumulateNormalEquations(chunk, lightSet_, chunkObservations(band, r, x0),
                                              settings_.fit.harmonics, settings_.fit.precision,
                                              *sums);
                    solveNormalEquations(*sums, settings_.fit.harmonics, settings_.fit.lambda,
                                         *plain);
                }
                for (int lane = 0; lane < kLanes && x0 + lane < band.width; ++lane) {
                    const std::size_t p = rows.pixel(r, x0 + lane);
                    const bool valid = laneValid[lane] && solution.valid[lane];
                    rows.valid[p] = valid ? 1 : 0;
                    for (int a = 0; a < 3; ++a) {
                        rows.normal[p * 3 + a] = chunk.normal[a][lane];
                    }
                    if (!valid) {
                        continue;  // coefficients and RMS stay zero
                    }
                    for (int c = 0; c < kChannels; ++c) {
                        std::copy_n(solution.coefficients[lane][c], coefficients,
                                    rows.coefficient.begin() +
                                        static_cast<long>((p * kChannels + c) * coefficients));
                        rows.rms[p * kChannels + c] = solution.rms[lane][c];
                    }
                    if (settings_.extended) {
                        std::copy_n(withTransport->transport[lane], model::kTransportValues,
                                    rows.transport.begin() +
                                        static_cast<long>(p * model::kTransportValues));
                    }
                }
            }
        });
}

}  // namespace vpe::fit
