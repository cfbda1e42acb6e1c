// SPDX-License-Identifier: MIT
// Real spherical harmonics, bands 0..3.
#include "vpe/model/light_transport.h"

#include <algorithm>
#include <cmath>

namespace vpe::model {

void lightTransportBasis(const proto::Vec3d& d, double* b) {
    const double x = d.x, y = d.y, z = d.z;
    // Normalization constants of the real SH basis (Sloan, "Stupid SH tricks").
    b[0] = 0.282094791773878;
    b[1] = 0.488602511902920 * y;
    b[2] = 0.488602511902920 * z;
    b[3] = 0.488602511902920 * x;
    b[4] = 1.092548430592079 * x * y;
    b[5] = 1.092548430592079 * y * z;
    b[6] = 0.315391565252520 * (3 * z * z - 1);
    b[7] = 1.092548430592079 * x * z;
    b[8] = 0.546274215296040 * (x * x - y * y);
    b[9] = 0.590043589926644 * y * (3 * x * x - y * y);
    b[10] = 2.890611442640554 * x * y * z;
    b[11] = 0.457045799464466 * y * (5 * z * z - 1);
    b[12] = 0.373176332590115 * z * (5 * z * z - 3);
    b[13] = 0.457045799464466 * x * (5 * z * z - 1);
    b[14] = 1.445305721320277 * z * (x * x - y * y);
    b[15] = 0.590043589926644 * x * (x * x - 3 * y * y);
}

void identityTransport(double* coefficients) {
    for (int i = 0; i < kTransportTerms; ++i) {
        coefficients[i] = 0.0;
    }
    coefficients[0] = 1.0 / 0.282094791773878;
}

std::array<double, kTransportChannels> evaluateColourTransport(const float* values,
                                                               const proto::Vec3d& direction) {
    double basis[kTransportTerms];
    lightTransportBasis(direction, basis);
    std::array<double, kTransportChannels> t{};
    for (int c = 0; c < kTransportChannels; ++c) {
        double value = 0;
        for (int i = 0; i < kTransportTerms; ++i) {
            value += static_cast<double>(values[c * kTransportTerms + i]) * basis[i];
        }
        t[static_cast<std::size_t>(c)] = std::max(0.0, value);
    }
    return t;
}

proto::Vec3d transportDirection(const capture::Capture& capture,
                                const capture::CaptureImage& image) {
    return capture.lightKind == capture::LightKind::kPoint ? proto::normalized(image.light)
                                                           : image.light;
}

}  // namespace vpe::model
