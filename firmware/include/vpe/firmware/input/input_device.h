// SPDX-License-Identifier: MIT
// InputDevice: an input backend the player's event loop polls. It owns its file descriptors
// (GPIO line event fds, an eventfd its camera thread signals, the OSC socket) and turns their
// readiness into InputEvents. The loop never blocks in a device: onReadable drains without
// waiting, and onTick lets a device act on time alone (debounce ends, a lost lamp's hold time).
#pragma once

#include <cstdint>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "vpe/firmware/input/input_event.h"

namespace vpe::firmware {

class InputDevice {
public:
    virtual ~InputDevice() = default;
    InputDevice() = default;
    InputDevice(const InputDevice&) = delete;
    InputDevice& operator=(const InputDevice&) = delete;

    // For logs: "knobs (gpiochip0)", "camera (imx219 320x240)", "osc (127.0.0.1:9000)".
    virtual std::string description() const = 0;
    // The descriptors to poll for reading; stable for the device's life.
    virtual std::vector<int> pollDescriptors() const = 0;
    // `fd` is readable: read what is there without blocking, append the decoded events.
    virtual void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) = 0;
    // Called at least once per frame with CLOCK_MONOTONIC now.
    virtual void onTick(std::int64_t /*nowNs*/, std::vector<InputEvent>& /*events*/) {}
    // What the device refused before it became an event, counted per reason over its life
    // ("osc.out_of_range": 3); the player's report carries them. Reasons with no refusal may
    // be left out.
    virtual std::map<std::string, std::uint64_t> refusals() const { return {}; }
    // What the device did besides events, over its life ("bus.published": 12); the player's
    // report carries them as `counters`.
    virtual std::map<std::string, std::uint64_t> counters() const { return {}; }
};

// CLOCK_MONOTONIC in nanoseconds: the clock of GPIO event timestamps (libgpiod 1.6 reports
// CLOCK_MONOTONIC by default), libcamera's SensorTimestamp and the loop's timer.
inline std::int64_t monotonicNowNs() {
    timespec now{};
    ::clock_gettime(CLOCK_MONOTONIC, &now);
    return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

}  // namespace vpe::firmware
