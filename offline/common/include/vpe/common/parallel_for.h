// SPDX-License-Identifier: MIT
// parallelFor: splits [0, count) into chunks handed to a fixed number of threads. Results
// must not depend on the thread count, so callers write each index's output in place.
#pragma once

#include <cstddef>
#include <functional>

namespace vpe::common {

// 0 means one thread per hardware thread.
unsigned resolveThreadCount(int requested);

// Calls body(begin, end) on disjoint chunks of at most `grain` indices. The first exception a
// chunk throws is rethrown on the calling thread after all threads have stopped.
void parallelFor(std::size_t count, std::size_t grain, unsigned threads,
                 const std::function<void(std::size_t begin, std::size_t end)>& body);

}  // namespace vpe::common
