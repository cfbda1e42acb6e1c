// SPDX-License-Identifier: MIT
// A rig written as kamino410/procam-calibration's calibrate.py writes calibration_result.xml
// (OpenCV's XML FileStorage from Python): img_shape (the camera image's rows, cols), rms,
// cam_int, cam_dist, proj_int, proj_dist, rotation, translation (camera → projector, in the
// chessboard's unit); no projector size. For the tests of the files vpe reads from other tools.
#pragma once

#include <array>
#include <cstdio>
#include <string>

#include "vpe/proto/pinhole_camera.h"

namespace vpe::testing {

// One matrix element as the tool's files hold them (%.17g: read back exactly).
inline std::string toolNumber(double value) {
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%.17g", value);
    return text.data();
}

template <std::size_t N>
std::string toolMatrix(const std::string& key, int rows, int cols,
                       const std::array<double, N>& values, double scale = 1.0) {
    std::string text = "<" + key + " type_id=\"opencv-matrix\">\n  <rows>" + std::to_string(rows) +
                       "</rows>\n  <cols>" + std::to_string(cols) +
                       "</cols>\n  <dt>d</dt>\n  <data>\n   ";
    for (const double value : values) {
        text += " " + toolNumber(value * scale);
    }
    return text + "</data></" + key + ">\n";
}

// The file's text: `projector` in the camera's frame (x_projector = R·x_camera + T, metres, as
// vpe's files hold it), its translation written in units of `metresPerUnit` (0.001: the
// millimetres of a board measured in mm); `rotationKey` "roration" as the tool's first versions
// spelt it.
inline std::string toolCalibrationXml(const proto::PinholeCamera& projector,
                                      const proto::PinholeCamera& camera, double rms,
                                      double metresPerUnit = 0.001,
                                      const std::string& rotationKey = "rotation") {
    const std::array<double, 2> shape{double(camera.height), double(camera.width)};
    return "<?xml version=\"1.0\"?>\n<opencv_storage>\n" + toolMatrix("img_shape", 2, 1, shape) +
           "<rms>" + toolNumber(rms) + "</rms>\n" + toolMatrix("cam_int", 3, 3, camera.K) +
           toolMatrix("cam_dist", 1, 5, camera.distortion) +
           toolMatrix("proj_int", 3, 3, projector.K) +
           toolMatrix("proj_dist", 1, 5, projector.distortion) +
           toolMatrix(rotationKey, 3, 3, projector.R) +
           toolMatrix("translation", 3, 1, projector.T, 1 / metresPerUnit) + "</opencv_storage>\n";
}

}  // namespace vpe::testing
