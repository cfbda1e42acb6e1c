// SPDX-License-Identifier: MIT
// Held-out poses: a calibration judged by what it predicts. Each pose in turn is left out; the
// others are calibrated as the full calibration is (calibrateProcam); the left-out board's pose
// is found from its camera corners alone, and its corners are predicted in the projector
// through the held-in R, T and projector model, against the corners decoded there. A few poses
// can hold a projector loosely while fitting their own corners well; this is what shows it.
#pragma once

#include <filesystem>
#include <vector>

#include "vpe/calibrate/board_spec.h"
#include "vpe/calibrate/procam_calibrator.h"

namespace vpe::calibrate {

struct HeldOutPose {
    std::filesystem::path folder;
    int corners = 0;  // the pose's corners decoded in the projector
    double rms = 0;   // pixels: predicted against decoded, over those corners
};

struct HeldOutPoses {
    // Over every held-out corner of every pose: the RMS and the median distance, pixels.
    double rms = 0, median = 0;
    std::vector<HeldOutPose> poses;  // in the poses' order
};

// The calibration's own minimum (3 poses) held in, so at least 4 poses; throws InputError
// below that, and when a held-in calibration or a pose's camera corners do not determine one.
HeldOutPoses evaluateHeldOutPoses(const std::vector<BoardPose>& poses, const BoardSpec& board);

}  // namespace vpe::calibrate
