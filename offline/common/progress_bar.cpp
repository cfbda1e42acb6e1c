// SPDX-License-Identifier: MIT
// ProgressBar: drawn with carriage returns on a TTY only.
#include "vpe/common/progress_bar.h"

#include <cstdio>
#include <utility>

#include <unistd.h>

namespace vpe::common {

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total == 0 ? 1 : total),
      enabled_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

ProgressBar::~ProgressBar() {
    finish();
}

void ProgressBar::advance(std::size_t steps) {
    maybeDraw(done_.fetch_add(steps) + steps);
}

void ProgressBar::setPhase(std::string phase) {
    if (!enabled_) {
        return;
    }
    {
        std::lock_guard lock(drawMutex_);
        phase_ = std::move(phase);
    }
    maybeDraw(done_.load());
}

void ProgressBar::setPhase(std::string_view phase, std::initializer_list<StepSeconds> steps) {
    if (!enabled_) {
        return;
    }
    std::string text(phase);
    const char* separator = "  (";
    for (const StepSeconds& step : steps) {
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, " %.1f s", step.seconds);
        text += separator;
        text += step.name;
        text += seconds;
        separator = ", ";
    }
    if (steps.size() > 0) {
        text += ')';
    }
    setPhase(std::move(text));
}

void ProgressBar::maybeDraw(std::size_t done) {
    if (!enabled_) {
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(drawMutex_, std::try_to_lock);
    if (lock.owns_lock() && now - lastDraw_ > std::chrono::milliseconds(100)) {
        lastDraw_ = now;
        draw(done, false);
    }
}

void ProgressBar::finish() {
    std::lock_guard lock(drawMutex_);
    if (finished_) {
        return;
    }
    finished_ = true;
    if (enabled_) {
        draw(done_.load(), true);
        std::fputc('\n', stderr);
    }
}

void ProgressBar::draw(std::size_t done, bool final) {
    constexpr int kWidth = 30;
    const double fraction = done >= total_ ? 1.0 : static_cast<double>(done) / total_;
    const int filled = static_cast<int>(fraction * kWidth);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) {
        bar[i] = i < filled ? '#' : '.';
    }
    bar[kWidth] = '\0';
    const std::string phase = phase_.empty() ? "" : "  " + phase_;
    // \x1b[K clears what a longer previous line left behind.
    if (final || fraction <= 0.0) {
        std::fprintf(stderr, "\r%-12s [%s] %5.1f%%  %.1f s%s\x1b[K", label_.c_str(), bar,
                     100.0 * fraction, elapsed, phase.c_str());
    } else {
        const double remaining = elapsed * (1.0 - fraction) / fraction;
        std::fprintf(stderr, "\r%-12s [%s] %5.1f%%  %.1f s, %.0f s left%s\x1b[K", label_.c_str(),
                     bar, 100.0 * fraction, elapsed, remaining, phase.c_str());
    }
    std::fflush(stderr);
}

}  // namespace vpe::common
