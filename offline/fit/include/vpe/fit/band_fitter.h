// SPDX-License-Identifier: MIT
// BandFitter: fits every pixel of a band of decoded rows, on all threads — the inner stage of
// `vpe fit` (and what the fitting benchmark measures). The paper's model is one accumulation
// and solve per chunk of kLanes pixels; the extended model alternates BRDF and transport.
#pragma once

#include <memory>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/sample_band.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/fit/extended_chunk_fit.h"
#include "vpe/fit/normal_equations.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/normals/normal_map.h"

namespace vpe::fit {

struct BandFitSettings {
    // M, λ and the precision of either model's fit; the rest for the extended model only
    // (with normalSearchDegrees > 0, ModelRows::normal holds the refined normals).
    ExtendedFitSettings fit;
    bool extended = false;
    unsigned threads = 1;
};

class BandFitter {
public:
    // `capture` is the geometry the fit runs under (calibrated, for the extended model);
    // all references must outlive the fitter.
    BandFitter(const capture::Capture& capture, const capture::SurfaceGeometry& geometry,
               const normals::NormalMap& normals, const BandFitSettings& settings);

    // Fits rows band.rowBegin .. + band.rows into `rows` (resized here).
    void fit(const capture::SampleBand& band, model::ModelRows& rows) const;

private:
    const capture::Capture& capture_;
    const capture::SurfaceGeometry& geometry_;
    const normals::NormalMap& normals_;
    BandFitSettings settings_;
    std::vector<KernelLight> lights_;
    KernelLightSet lightSet_;
    std::unique_ptr<ExtendedLightTable> lightTable_;
};

}  // namespace vpe::fit
