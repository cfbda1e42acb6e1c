// SPDX-License-Identifier: MIT
// Runs a per-row function over an image's rows on several threads. Rows are handed out one at
// a time from a shared counter; each row's result depends only on the row, so the output does
// not depend on the number of threads.
#pragma once

#include <functional>

namespace vpe::renderer {

// threads ≤ 0: std::thread::hardware_concurrency(). The caller's thread works too. An
// exception thrown by `row` stops the remaining rows and is rethrown here.
void forEachRow(int height, int threads, const std::function<void(int row)>& row);

}  // namespace vpe::renderer
