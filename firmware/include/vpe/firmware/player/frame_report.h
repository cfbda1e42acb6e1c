// SPDX-License-Identifier: MIT
// FrameReport: what vpe-player measured, for its summary line and its --json object: frame
// times, input-to-frame latency (event timestamp → frame submitted), resident memory at the
// start and the end (a soak must stay flat), input counts and errors.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace vpe::firmware {

// Nearest rank: the smallest value with at least q of the samples at or below it (0 if none).
double nearestRankPercentile(std::vector<double> values, double q);

// The process's resident set in KiB (/proc/self/statm), 0 when unreadable.
long residentKilobytes();

std::string jsonString(const std::string& text);

// Keeps every sample up to a cap, then a uniform reservoir (percentiles of a 16,384-sample
// reservoir are within a fraction of a percent of the exact ones): a player running for
// months must not grow memory for its own statistics. The storage is allocated and written
// up front, so its pages are resident from the start.
class SampleSet {
public:
    explicit SampleSet(std::size_t capacity = 16'384)
        : samples_(capacity, 0.0), capacity_(capacity) {}
    void add(double value);
    std::size_t count() const { return count_; }
    double max() const { return max_; }
    double mean() const { return count_ == 0 ? 0 : total_ / static_cast<double>(count_); }
    double percentile(double q) const {
        return nearestRankPercentile(
            std::vector<double>(samples_.begin(),
                                samples_.begin() + static_cast<std::ptrdiff_t>(stored_)),
            q);
    }

private:
    std::vector<double> samples_;
    std::size_t capacity_;
    std::size_t stored_ = 0;
    std::size_t count_ = 0;
    double total_ = 0;
    double max_ = 0;
    std::uint64_t random_ = 0x9E3779B97F4A7C15ull;
};

struct FrameReport {
    long frames = 0;   // drawn
    long skipped = 0;  // ticks with nothing changed: not drawn (frames + skipped = ticks)
    int width = 0, height = 0;
    std::string preset, platform;
    SampleSet frameMs;
    SampleSet latencyMs;      // one sample per applied input event
    double firstFrameMs = 0;  // process start → first frame submitted
    double seconds = 0;       // first frame → last frame
    // After the first frame, after 1,000 frames (caches, allocator pools and the statistics'
    // reservoirs warmed up), and at the end: a soak is flat when end ≈ warm.
    long rssStartKb = 0, rssWarmKb = 0, rssEndKb = 0;
    long written = 0;
    long reloads = 0, reloadsRefused = 0;
    long errors = 0;  // frames that failed (GL errors): the loop logs and goes on
    std::map<std::string, long> events;  // per source: "knobs", "camera", "osc"
    // Everything refused on the way from an input to the light, per reason: what the inputs
    // refused before an event existed ("osc.out_of_range", "osc.malformed_packet", ...) and
    // events the light rig refused ("light.preset_out_of_range"). eventsRefused is their sum.
    std::map<std::string, std::uint64_t> refusedByReason;
    long eventsRefused = 0;
    // What the inputs did besides events ("bus.published", "bus.connections", ...), and the
    // light rig's "light.stale_states" (other nodes' states older than its own).
    std::map<std::string, std::uint64_t> counters;
    std::string stoppedBy = "frames";
    // The light at the end: where the inputs (or the drift) left it.
    double azimuthDeg = 0, elevationDeg = 0, distanceM = 0;
    std::string activeInput;  // "frames", "SIGTERM", "SIGINT", "replay"

    // 1000 / mean frame time: what the renderer sustains (0 before any frame).
    double fps() const { return frameMs.mean() > 0 ? 1000.0 / frameMs.mean() : 0; }

    std::string summaryLine() const;
    std::string json() const;
};

}  // namespace vpe::firmware
