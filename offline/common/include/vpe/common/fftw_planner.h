// SPDX-License-Identifier: MIT
// fftwPlannerMutex: the one lock every FFTW user in offline/ holds while it plans or destroys
// a plan. FFTW's planner keeps global state and is not thread-safe; executing an existing
// plan (fftwf_execute_dft_r2c and friends on new arrays) is, and needs no lock.
#pragma once

#include <mutex>

namespace vpe::common {

std::mutex& fftwPlannerMutex();

}  // namespace vpe::common
