// SPDX-License-Identifier: MIT
// One process-wide mutex, so that two rooms (quilting and its quality measures) planning at
// the same time on different threads do not corrupt FFTW's planner.
#include "vpe/common/fftw_planner.h"

namespace vpe::common {

std::mutex& fftwPlannerMutex() {
    static std::mutex mutex;
    return mutex;
}

}  // namespace vpe::common
