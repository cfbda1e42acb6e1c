// SPDX-License-Identifier: MIT
// parallelFor: an atomic chunk counter shared by std::threads.
#include "vpe/common/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace vpe::common {

unsigned resolveThreadCount(int requested) {
    if (requested > 0) {
        return static_cast<unsigned>(requested);
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

void parallelFor(std::size_t count, std::size_t grain, unsigned threads,
                 const std::function<void(std::size_t, std::size_t)>& body) {
    if (count == 0) {
        return;
    }
    grain = std::max<std::size_t>(grain, 1);
    const std::size_t chunks = (count + grain - 1) / grain;
    const unsigned workers = static_cast<unsigned>(std::min<std::size_t>(threads, chunks));
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failureMutex;
    auto work = [&] {
        for (;;) {
            const std::size_t chunk = next.fetch_add(1);
            if (chunk >= chunks) {
                return;
            }
            try {
                const std::size_t begin = chunk * grain;
                body(begin, std::min(count, begin + grain));
            } catch (...) {
                std::lock_guard lock(failureMutex);
                if (!failure) {
                    failure = std::current_exception();
                }
                next.store(chunks);  // stop handing out work
            }
        }
    };
    if (workers <= 1) {
        work();
    } else {
        std::vector<std::jthread> pool;
        pool.reserve(workers - 1);
        for (unsigned i = 1; i < workers; ++i) {
            pool.emplace_back(work);
        }
        work();
    }
    if (failure) {
        std::rethrow_exception(failure);
    }
}

}  // namespace vpe::common
