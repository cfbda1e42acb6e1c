// SPDX-License-Identifier: MIT
// A model's prediction of a capture's images.
#include "vpe/eval/capture_predictor.h"

#include <algorithm>

#include "vpe/capture/geometry_calibration.h"
#include "vpe/model/light_transport.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::eval {

CapturePredictor::CapturePredictor(const model::ModelInfo& info, const capture::Capture& capture,
                                   const capture::TransferFunction& stored)
    : info_(info),
      // A model fitted under a calibrated geometry and response predicts other captures of
      // the same dome under them too.
      capture_(
          capture::applyAcceptedCalibration(capture, info.calibration, info.width, info.height)),
      stored_(stored),
      metric_(capture::metricTransfer(capture_)),
      geometry_(capture_, info.width, info.height),  // normals come from the model
      rti_(info.rtiBasis()) {
    const std::size_t lights = capture_.images.size();
    if (rti_) {
        rtiBasisValues_.resize(lights * static_cast<std::size_t>(rti_->terms));
        for (std::size_t s = 0; s < lights; ++s) {
            rti_->evaluate(capture_.images[s].light,
                           &rtiBasisValues_[s * static_cast<std::size_t>(rti_->terms)]);
        }
    }
    if (info_.hasTransport()) {
        for (const capture::CaptureImage& image : capture_.images) {
            transportDirections_.push_back(model::transportDirection(capture_, image));
        }
    }
}

std::array<double, 3> CapturePredictor::predict(const model::ModelRows& rows, int row, int x, int y,
                                                int light) const {
    const std::size_t s = static_cast<std::size_t>(light);
    std::array<double, 3> out{};
    if (rti_) {
        // An RTI basis predicts the stored values, which are decoded first.
        const double* basis = &rtiBasisValues_[s * static_cast<std::size_t>(rti_->terms)];
        for (int c = 0; c < 3; ++c) {
            const float* coefficients = rows.coefficientsAt(row, x, c);
            double value = 0;
            for (int k = 0; k < rti_->terms; ++k) {
                value += basis[k] * static_cast<double>(coefficients[k]);
            }
            out[static_cast<std::size_t>(c)] =
                metric_.encode(std::clamp(stored_.decode(value), 0.0, 1.0));
        }
        return out;
    }
    const std::size_t p = rows.pixel(row, x);
    const proto::Vec3d normal{rows.normal[p * 3], rows.normal[p * 3 + 1], rows.normal[p * 3 + 2]};
    const capture::IncidentLight incident =
        capture::incidentLight(capture_, capture_.images[s], geometry_.position(x, y));
    const auto angles =
        proto::reflectionAngles(normal, incident.direction, geometry_.toViewer(x, y));
    // The extended model's capture-specific light transport (cast shadows, interreflection)
    // of this texel under this light, per colour channel.
    const std::array<double, model::kTransportChannels> transport =
        rows.transport.empty()
            ? std::array<double, model::kTransportChannels>{1.0, 1.0, 1.0}
            : model::evaluateColourTransport(&rows.transport[p * model::kTransportValues],
                                             transportDirections_[s]);
    for (int c = 0; c < 3; ++c) {
        const double predicted =
            transport[static_cast<std::size_t>(c)] * incident.irradiance *
            proto::evaluateFourierBrdf(rows.coefficientsAt(row, x, c), info_.harmonics,
                                       angles.cosThetaD, angles.cosThetaS);
        out[static_cast<std::size_t>(c)] = metric_.encode(std::clamp(predicted, 0.0, 1.0));
    }
    return out;
}

}  // namespace vpe::eval
