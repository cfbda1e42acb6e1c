// SPDX-License-Identifier: MIT
// ProgressBar: a one-line bar on stderr for long offline work, with the phase under way (and
// the time each phase took so far); silent when stderr is not a terminal (CI logs, pipes), so
// scripted output stays clean.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <initializer_list>
#include <mutex>
#include <string>
#include <string_view>

namespace vpe::common {

// The time one kind of step (decode, fit, write…) has taken so far.
struct StepSeconds {
    const char* name;
    double seconds;
};

class ProgressBar {
public:
    ProgressBar(std::string label, std::size_t total);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    // Thread-safe; redraws at most ten times a second.
    void advance(std::size_t steps = 1);
    // What is under way, shown after the bar.
    void setPhase(std::string phase);
    // The same, followed by the time each kind of step has taken so far:
    // "decoding  (decode 3.1 s, fit 2.0 s, write 1.2 s)". A pipeline that alternates its steps
    // band by band (vpe fit, vpe quilt) shows where the time goes while it runs.
    void setPhase(std::string_view phase, std::initializer_list<StepSeconds> steps);
    void finish();

private:
    void maybeDraw(std::size_t done);
    void draw(std::size_t done, bool final);

    std::string label_;
    std::size_t total_;
    bool enabled_;
    bool finished_ = false;
    std::atomic<std::size_t> done_{0};
    std::mutex drawMutex_;
    std::string phase_;  // guarded by drawMutex_
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace vpe::common
