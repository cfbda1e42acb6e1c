// SPDX-License-Identifier: MIT
// KnobEdgeSink: line levels, routing, and the events of detents and presses.
#include "vpe/firmware/knobs/knob_edge_sink.h"

#include <cmath>

#include "vpe/firmware/knobs/knob_events.h"

namespace vpe::firmware::knobs {

namespace {

bool levelOf(const LineLevels& initial, unsigned line, bool idle) {
    const auto found = initial.find(line);
    return found == initial.end() ? idle : found->second;
}

std::int64_t nanoseconds(double ms) {
    return static_cast<std::int64_t>(std::llround(ms * 1e6));
}

}  // namespace

KnobEdgeSink::KnobEdgeSink(const KnobsConfig& config, const LineLevels& initial,
                           std::int64_t startNs) {
    encoders_.reserve(config.encoders.size());
    for (const EncoderConfig& encoder : config.encoders) {
        const bool a = levelOf(initial, encoder.lineA, true);
        const bool b = levelOf(initial, encoder.lineB, true);
        levels_[encoder.lineA] = a;
        levels_[encoder.lineB] = b;
        routes_[encoder.lineA] = Route{Route::Kind::kEncoderA, encoders_.size()};
        routes_[encoder.lineB] = Route{Route::Kind::kEncoderB, encoders_.size()};
        encoders_.push_back(Encoder{encoder, QuadratureDecoder(encoder.stepsPerDetent, a, b),
                                    TurnAccelerator(encoder.acceleration)});
    }
    buttons_.reserve(config.buttons.size());
    for (const ButtonConfig& button : config.buttons) {
        const bool level = levelOf(initial, button.line, button.activeLow);
        levels_[button.line] = level;
        routes_[button.line] = Route{Route::Kind::kButton, buttons_.size()};
        buttons_.push_back(Button{button, DebouncedButton(nanoseconds(button.debounceMs),
                                                          button.activeLow, level, startNs)});
    }
}

bool KnobEdgeSink::onEdge(const LineEdge& edge, std::vector<InputEvent>& events) {
    const auto route = routes_.find(edge.line);
    if (route == routes_.end()) {
        return false;
    }
    // Presses that settled before this edge come first, so events stay in time order.
    settleButtons(edge.timestampNs, events);

    // The level comes from the edge's kind, not from toggling: after a lost event the next
    // edge puts the level right again (a repeated level is no transition).
    const bool level = edge.kind == EdgeKind::kRising;
    levels_[edge.line] = level;
    const std::size_t index = route->second.index;
    if (route->second.kind == Route::Kind::kButton) {
        Button& button = buttons_[index];
        if (std::optional<std::int64_t> press = button.debounced.onEdge(level, edge.timestampNs)) {
            events.push_back(buttonEvent(button.config.action, *press));
        }
        return true;
    }
    Encoder& encoder = encoders_[index];
    const bool a = levels_[encoder.config.lineA];
    const bool b = levels_[encoder.config.lineB];
    if (std::optional<Detent> detent = encoder.decoder.update(a, b, edge.timestampNs)) {
        const double factor = encoder.accelerator.factorFor(detent->direction, detent->timestampNs);
        events.push_back(turnEvent(encoder.config, detent->direction, factor, detent->timestampNs));
    }
    return true;
}

void KnobEdgeSink::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    settleButtons(nowNs, events);
}

void KnobEdgeSink::settleButtons(std::int64_t nowNs, std::vector<InputEvent>& events) {
    for (Button& button : buttons_) {
        if (std::optional<std::int64_t> press = button.debounced.onTick(nowNs)) {
            events.push_back(buttonEvent(button.config.action, *press));
        }
    }
}

std::vector<unsigned> KnobEdgeSink::lines() const {
    std::vector<unsigned> lines;
    lines.reserve(routes_.size());
    for (const auto& [line, route] : routes_) {
        (void)route;
        lines.push_back(line);
    }
    return lines;
}

}  // namespace vpe::firmware::knobs
