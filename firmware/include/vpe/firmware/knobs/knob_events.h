// SPDX-License-Identifier: MIT
// Knob events: what a detent or a button press means for the light, as an InputEvent from
// InputSource::kKnobs stamped with the edge that caused it.
#pragma once

#include <cstdint>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/knobs/knobs_config.h"

namespace vpe::firmware::knobs {

// TurnLight on the encoder's axis by direction × step × factor (direction ±1, clockwise +1;
// `reverse` flips it; factor from the turn acceleration).
InputEvent turnEvent(const EncoderConfig& encoder, int direction, double factor,
                     std::int64_t timestampNs);

// SelectPreset{+1 or −1, relative} for next/previous preset, ResetLight for reset.
InputEvent buttonEvent(ButtonAction action, std::int64_t timestampNs);

}  // namespace vpe::firmware::knobs
