// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/frame_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace vpe::firmware {

double nearestRankPercentile(std::vector<double> values, double q) {
    if (values.empty()) {
        return 0;
    }
    std::sort(values.begin(), values.end());
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
    return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

long residentKilobytes() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    if (!(statm >> size >> resident)) {
        return 0;
    }
    return resident * (::sysconf(_SC_PAGESIZE) / 1024);
}

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

void SampleSet::add(double value) {
    ++count_;
    total_ += value;
    max_ = count_ == 1 ? value : std::max(max_, value);
    if (stored_ < capacity_) {
        samples_[stored_++] = value;
        return;
    }
    // Algorithm R with a xorshift generator: each sample kept with probability capacity/count.
    random_ ^= random_ << 13;
    random_ ^= random_ >> 7;
    random_ ^= random_ << 17;
    const std::uint64_t slot = random_ % count_;
    if (slot < capacity_) {
        samples_[slot] = value;
    }
}

std::string FrameReport::summaryLine() const {
    std::ostringstream line;
    line << "vpe-player: " << frames << " frames " << width << "x" << height << ", preset '"
         << preset << "', on " << platform << ": " << fps() << " fps, frame p50 "
         << frameMs.percentile(0.5) << " ms, p99 " << frameMs.percentile(0.99)
         << " ms; first frame " << firstFrameMs << " ms after start";
    if (latencyMs.count() > 0) {
        line << "; input latency p50 " << latencyMs.percentile(0.5) << " ms, p99 "
             << latencyMs.percentile(0.99) << " ms over " << latencyMs.count() << " events";
    }
    line << "; RSS " << rssStartKb << " → " << rssEndKb << " KiB";
    if (skipped > 0) {
        line << "; " << skipped << " ticks skipped (nothing changed)";
    }
    if (written > 0) {
        line << "; " << written << " frames written";
    }
    if (errors > 0) {
        line << "; " << errors << " frame errors";
    }
    return line.str();
}

std::string FrameReport::json() const {
    std::ostringstream json;
    json << "{\"frames\": " << frames << ", \"skipped\": " << skipped << ", \"width\": " << width
         << ", \"height\": " << height << ", \"preset\": " << jsonString(preset)
         << ", \"platform\": " << jsonString(platform) << ", \"fps\": " << fps()
         << ", \"frame_ms\": {\"p50\": " << frameMs.percentile(0.5)
         << ", \"p99\": " << frameMs.percentile(0.99) << ", \"mean\": " << frameMs.mean()
         << ", \"max\": " << frameMs.max() << "}, \"first_frame_ms\": " << firstFrameMs
         << ", \"seconds\": " << seconds << ", \"latency_ms\": {\"events\": " << latencyMs.count()
         << ", \"p50\": " << latencyMs.percentile(0.5)
         << ", \"p99\": " << latencyMs.percentile(0.99) << ", \"max\": " << latencyMs.max()
         << "}, \"rss_kb\": {\"start\": " << rssStartKb << ", \"warm\": " << rssWarmKb
         << ", \"end\": " << rssEndKb << "}, \"events\": {";
    bool first = true;
    for (const auto& [source, count] : events) {
        json << (first ? "" : ", ") << jsonString(source) << ": " << count;
        first = false;
    }
    json << "}, \"events_refused\": " << eventsRefused << ", \"refused\": {";
    first = true;
    for (const auto& [reason, count] : refusedByReason) {
        json << (first ? "" : ", ") << jsonString(reason) << ": " << count;
        first = false;
    }
    json << "}, \"counters\": {";
    first = true;
    for (const auto& [name, count] : counters) {
        json << (first ? "" : ", ") << jsonString(name) << ": " << count;
        first = false;
    }
    json << "}, \"reloads\": " << reloads << ", \"reloads_refused\": " << reloadsRefused
         << ", \"errors\": " << errors << ", \"written\": " << written
         << ", \"stopped_by\": " << jsonString(stoppedBy)
         << ", \"light\": {\"azimuth\": " << azimuthDeg << ", \"elevation\": " << elevationDeg
         << ", \"distance\": " << distanceM << ", \"active\": " << jsonString(activeInput) << "}}";
    return json.str();
}

}  // namespace vpe::firmware
