// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/light_log.h"

#include <cerrno>
#include <cstring>
#include <string>

namespace vpe::firmware {

namespace {

// Lines between flushes: half a second at 60 Hz, so a node killed outright (a fault test)
// leaves its log up to then.
constexpr int kLinesPerFlush = 30;

}  // namespace

LightLog::LightLog(const std::filesystem::path& path) : file_(std::fopen(path.c_str(), "w")) {
    if (file_ == nullptr) {
        throw LightLogError(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    }
}

LightLog::~LightLog() {
    std::fclose(file_);
}

void LightLog::record(std::int64_t presentationRealtimeNs, const SphericalPosition& light,
                      const char* active, bool drawn) {
    std::fprintf(file_,
                 "{\"t_us\": %lld, \"azimuth\": %.6f, \"elevation\": %.6f, \"distance\": %.6f, "
                 "\"active\": \"%s\", \"drawn\": %s}\n",
                 static_cast<long long>(presentationRealtimeNs / 1000), light.azimuthDeg,
                 light.elevationDeg, light.distanceM, active, drawn ? "true" : "false");
    if (++unflushed_ >= kLinesPerFlush) {
        flush();
    }
}

void LightLog::flush() {
    std::fflush(file_);
    unflushed_ = 0;
}

}  // namespace vpe::firmware
