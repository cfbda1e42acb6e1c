// SPDX-License-Identifier: MIT
// Knob events: detents and presses → InputEvents.
#include "vpe/firmware/knobs/knob_events.h"

namespace vpe::firmware::knobs {

InputEvent turnEvent(const EncoderConfig& encoder, int direction, double factor,
                     std::int64_t timestampNs) {
    const double amount = (encoder.reverse ? -direction : direction) * encoder.step * factor;
    TurnLight turn;
    switch (encoder.axis) {
        case KnobAxis::kAzimuth:
            turn.azimuthDeg = amount;
            break;
        case KnobAxis::kElevation:
            turn.elevationDeg = amount;
            break;
        case KnobAxis::kDistance:
            turn.distanceM = amount;
            break;
    }
    return InputEvent{InputSource::kKnobs, timestampNs, turn};
}

InputEvent buttonEvent(ButtonAction action, std::int64_t timestampNs) {
    switch (action) {
        case ButtonAction::kNextPreset:
            return InputEvent{InputSource::kKnobs, timestampNs, SelectPreset{+1, true}};
        case ButtonAction::kPreviousPreset:
            return InputEvent{InputSource::kKnobs, timestampNs, SelectPreset{-1, true}};
        case ButtonAction::kReset:
            break;
    }
    return InputEvent{InputSource::kKnobs, timestampNs, ResetLight{}};
}

}  // namespace vpe::firmware::knobs
