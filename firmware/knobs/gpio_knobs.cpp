// SPDX-License-Identifier: MIT
// GpioKnobs: libgpiod 1.6 (the kernel's v1 character-device line events) behind InputDevice.
#include "vpe/firmware/knobs/gpio_knobs.h"

#include <cerrno>
#include <system_error>

#include <fcntl.h>
#include <gpiod.h>

#include "line_event_reader.h"

namespace vpe::firmware::knobs {

namespace {

std::string errnoText(int error) {
    if (error == ENOTTY || error == ENODEV) {
        return "not a GPIO chip: " + std::generic_category().message(error);
    }
    return std::generic_category().message(error);
}

std::string plural(std::size_t count, const char* noun) {
    return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

// A line to request: its offset, the board-file key that names it, and the bias it wants.
struct LineRequest {
    unsigned offset;
    std::string key;
    int biasFlag;
};

}  // namespace

void GpioKnobs::ChipCloser::operator()(gpiod_chip* chip) const {
    // Closing the chip releases every line requested from it (libgpiod 1.6 owns the lines).
    gpiod_chip_close(chip);
}

GpioKnobs::GpioKnobs(const KnobsConfig& config)
    : chipName_(config.chip),
      summary_(plural(config.encoders.size(), "encoder") + ", " +
               plural(config.buttons.size(), "button")) {
    if (config.encoders.empty() && config.buttons.empty()) {
        throw KnobsUnavailable(chipName_ +
                               ": no [[gpio.encoder]] or [[gpio.button]] lines to read");
    }

    // A path opens that node; anything else is a name, number or label ("gpiochip0", "0",
    // "pinctrl-rp1"), which gpiod_chip_open_lookup tries in turn.
    errno = 0;
    gpiod_chip* chip = chipName_.find('/') != std::string::npos
                           ? gpiod_chip_open(chipName_.c_str())
                           : gpiod_chip_open_lookup(chipName_.c_str());
    if (chip == nullptr) {
        throw KnobsUnavailable(chipName_ + ": cannot open GPIO chip (" +
                               errnoText(errno != 0 ? errno : ENOENT) + ")");
    }
    chip_.reset(chip);

    // Encoder contacts: pull-ups (a KY-040 has its own 10 kΩ ones on CLK and DT; the internal
    // ones also cover bare encoders). Buttons: pulled to their released level.
    std::vector<LineRequest> requests;
    for (std::size_t i = 0; i < config.encoders.size(); ++i) {
        const std::string key = "gpio.encoder[" + std::to_string(i) + "]";
        requests.push_back(
            {config.encoders[i].lineA, key + ".a", GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP});
        requests.push_back(
            {config.encoders[i].lineB, key + ".b", GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP});
    }
    for (std::size_t i = 0; i < config.buttons.size(); ++i) {
        requests.push_back({config.buttons[i].line, "gpio.button[" + std::to_string(i) + "].line",
                            config.buttons[i].activeLow ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP
                                                        : GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN});
    }

    LineLevels initial;
    for (const LineRequest& request : requests) {
        const std::string what =
            chipName_ + ": line " + std::to_string(request.offset) + " (" + request.key + ")";
        gpiod_line* line = gpiod_chip_get_line(chip, request.offset);
        if (line == nullptr) {
            throw KnobsUnavailable(what + ": not on this chip (it has " +
                                   std::to_string(gpiod_chip_num_lines(chip)) + " lines)");
        }
        int result = gpiod_line_request_both_edges_events_flags(line, config.consumer.c_str(),
                                                                request.biasFlag);
        if (result < 0 && errno == EINVAL) {
            // Kernels before 5.5 have no bias flags; the board's own pull-ups must do.
            result = gpiod_line_request_both_edges_events_flags(line, config.consumer.c_str(), 0);
        }
        if (result < 0) {
            const int error = errno;
            std::string why = std::generic_category().message(error);
            if (error == EBUSY && gpiod_line_consumer(line) != nullptr) {
                why += ", used by \"" + std::string(gpiod_line_consumer(line)) + "\"";
            }
            throw KnobsUnavailable(what + ": cannot request edge events (" + why + ")");
        }
        const int fd = gpiod_line_event_get_fd(line);
        if (fd < 0) {
            throw KnobsUnavailable(what + ": no event descriptor");
        }
        // Belt and braces: reads happen only after poll() said readable, and cannot block even
        // if another reader took the event first.
        const int flags = ::fcntl(fd, F_GETFL);
        if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
            throw KnobsUnavailable(what + ": cannot make its descriptor non-blocking (" +
                                   std::generic_category().message(errno) + ")");
        }
        const int level = gpiod_line_get_value(line);
        if (level < 0) {
            throw KnobsUnavailable(what + ": cannot read its level (" +
                                   std::generic_category().message(errno) + ")");
        }
        initial[request.offset] = level != 0;
        lines_.push_back(RequestedLine{request.offset, line, fd});
    }
    sink_ = std::make_unique<KnobEdgeSink>(config, initial, monotonicNowNs());
}

GpioKnobs::~GpioKnobs() = default;

std::string GpioKnobs::description() const {
    return "knobs (" + chipName_ + ": " + summary_ + ")";
}

std::vector<int> GpioKnobs::pollDescriptors() const {
    std::vector<int> fds;
    fds.reserve(lines_.size());
    for (const RequestedLine& line : lines_) {
        fds.push_back(line.fd);
    }
    return fds;
}

void GpioKnobs::onReadable(int /*fd*/, std::int64_t nowNs, std::vector<InputEvent>& events) {
    std::vector<LineEventDescriptor> descriptors;
    descriptors.reserve(lines_.size());
    for (const RequestedLine& line : lines_) {
        descriptors.push_back(LineEventDescriptor{line.offset, line.fd});
    }
    for (const LineEdge& edge : readPendingLineEdges(descriptors, chipName_)) {
        sink_->onEdge(edge, events);
    }
    sink_->onTick(nowNs, events);
}

void GpioKnobs::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    sink_->onTick(nowNs, events);
}

}  // namespace vpe::firmware::knobs
