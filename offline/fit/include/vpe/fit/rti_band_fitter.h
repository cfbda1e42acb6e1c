// SPDX-License-Identifier: MIT
// RtiBandFitter: fits an RTI basis (PTM, HSH) to every pixel of a band, the way RTI tools do:
// least squares on the images' stored values (code / full scale), one design shared by every
// pixel. What `vpe fit --model ptm6|hsh16` runs, so that the classic bases are scored by
// the same `vpe eval` as vpe's own models.
#pragma once

#include <Eigen/Dense>

#include "vpe/capture/capture.h"
#include "vpe/capture/sample_band.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/rti_basis.h"

namespace vpe::fit {

class RtiBandFitter {
public:
    // `stored` is the curve the band's linear values were decoded with; the fit undoes it.
    RtiBandFitter(const capture::Capture& capture, const model::RtiBasis& basis,
                  const capture::TransferFunction& stored, unsigned threads);

    // Fits rows band.rowBegin .. + band.rows into `rows` (resized here). A pixel with fewer
    // usable samples than the basis has terms is left invalid.
    void fit(const capture::SampleBand& band, model::ModelRows& rows) const;

private:
    model::RtiBasis basis_;
    capture::TransferFunction stored_;
    unsigned threads_;
    Eigen::MatrixXd design_;         // images × terms
    Eigen::MatrixXd pseudoInverse_;  // terms × images: the least-squares solution operator
};

}  // namespace vpe::fit
