// SPDX-License-Identifier: MIT
// GpioKnobs: the board's rotary encoders and buttons on a GPIO chip (libgpiod 1.6), as an
// InputDevice. It requests both-edge events on every configured line (pull-up bias where the
// kernel has it), reads the lines' levels once at start, and feeds every edge it drains, merged
// across lines by timestamp, to a KnobEdgeSink: the same decoding a replay runs.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/knobs/knob_edge_sink.h"
#include "vpe/firmware/knobs/knobs_config.h"

struct gpiod_chip;
struct gpiod_line;

namespace vpe::firmware::knobs {

// The knobs cannot be used: the chip is missing or not a GPIO chip, a line cannot be requested
// (busy, not on this chip), or a line's events cannot be read. One line naming the chip:
// "gpiochip0: cannot open GPIO chip (No such file or directory)".
class KnobsUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class GpioKnobs : public InputDevice {
public:
    // Opens config.chip and requests its lines; throws KnobsUnavailable. `config` comes from
    // parseKnobsConfig (distinct lines); it needs at least one encoder or button.
    explicit GpioKnobs(const KnobsConfig& config);
    ~GpioKnobs() override;

    // "knobs (gpiochip0: 2 encoders, 1 button)".
    std::string description() const override;
    // One event descriptor per requested line (libgpiod 1.6: the kernel's v1 line events).
    std::vector<int> pollDescriptors() const override;
    // Drains every line that has events (not only `fd`, so that A and B of an encoder are
    // merged by timestamp before decoding), without blocking. Throws KnobsUnavailable when a
    // line's events cannot be read.
    void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) override;
    // Settles debounced buttons.
    void onTick(std::int64_t nowNs, std::vector<InputEvent>& events) override;

private:
    struct ChipCloser {
        void operator()(gpiod_chip* chip) const;
    };
    struct RequestedLine {
        unsigned offset;
        gpiod_line* line;  // owned by the chip; released with it
        int fd;
    };

    std::string chipName_;
    std::string summary_;
    std::unique_ptr<gpiod_chip, ChipCloser> chip_;
    std::vector<RequestedLine> lines_;
    std::unique_ptr<KnobEdgeSink> sink_;
};

}  // namespace vpe::firmware::knobs
