// SPDX-License-Identifier: MIT
// LightLog: `vpe-player --light-log FILE`. One JSON line per frame tick: the frame's presentation
// time on CLOCK_REALTIME (microseconds) and the light drawn for it, so that the logs of the
// nodes of a show can be compared at equal times (tests/firmware/bus/, scripts/
// multi-node-report.sh):
//   {"t_us": 1718000000123456, "azimuth": 12.345678, "elevation": 30.000000,
//    "distance": 0.600000, "active": "bus", "drawn": true}
// Written through a buffer and flushed every half second of frames, and at the end.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "vpe/firmware/light/light_sphere.h"
#include "vpe/proto/input_error.h"

namespace vpe::firmware {

class LightLogError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

class LightLog {
public:
    // Creates or truncates the file. Throws LightLogError ("FILE: cannot write (…)").
    explicit LightLog(const std::filesystem::path& path);
    ~LightLog();
    LightLog(const LightLog&) = delete;
    LightLog& operator=(const LightLog&) = delete;

    void record(std::int64_t presentationRealtimeNs, const SphericalPosition& light,
                const char* active, bool drawn);
    void flush();

private:
    std::FILE* file_ = nullptr;
    int unflushed_ = 0;
};

}  // namespace vpe::firmware
