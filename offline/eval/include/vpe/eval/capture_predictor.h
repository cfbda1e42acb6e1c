// SPDX-License-Identifier: MIT
// CapturePredictor: what a fitted model predicts the capture's camera sees under each of the
// capture's lights — the Fourier BRDF under the capture's geometry times the extended model's
// light transport, or an RTI basis — encoded in [0, 1] the way people see it. One
// definition shared by `vpe eval` (scoring) and what exports a model's relit appearance.
#pragma once

#include <array>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/rti_basis.h"

namespace vpe::eval {

class CapturePredictor {
public:
    // `capture` names the lights to predict; a model fitted under a calibrated geometry
    // predicts under that geometry (applied here when the capture accepts one). `stored` is
    // the curve the capture's images were stored with (an RTI basis predicts stored values).
    CapturePredictor(const model::ModelInfo& info, const capture::Capture& capture,
                     const capture::TransferFunction& stored);

    const capture::Capture& capture() const { return capture_; }
    int lightCount() const { return static_cast<int>(capture_.images.size()); }

    // Prediction of pixel (x, y), row `row` of `rows`, under light `light` (an index into
    // capture().images), clamped to [0, 1] and encoded as metricTransfer(capture()) says:
    // sRGB, or the images' calibrated response. The pixel must hold a valid fit.
    std::array<double, 3> predict(const model::ModelRows& rows, int row, int x, int y,
                                  int light) const;

private:
    model::ModelInfo info_;
    capture::Capture capture_;
    capture::TransferFunction stored_;
    capture::TransferFunction
        metric_;  // what predictions are encoded in (capture/transfer_function.h)
    capture::SurfaceGeometry geometry_;
    std::optional<model::RtiBasis> rti_;
    std::vector<double> rtiBasisValues_;             // [light][term]
    std::vector<proto::Vec3d> transportDirections_;  // [light]
};

}  // namespace vpe::eval
