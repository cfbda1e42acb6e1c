// SPDX-License-Identifier: MIT
// KnobsConfig: the board's GPIO knobs, from its [gpio] section (firmware/knobs/README.md):
// which chip, which lines carry which rotary encoder or button, and what each one does.
#pragma once

#include <string>
#include <vector>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

#include "vpe/firmware/knobs/turn_acceleration.h"

namespace vpe::firmware::knobs {

// What an encoder turns: the light's azimuth or elevation (degrees) or distance (metres).
enum class KnobAxis { kAzimuth, kElevation, kDistance };

enum class ButtonAction { kNextPreset, kPreviousPreset, kReset };

// "azimuth", "next-preset", …: the board file's spelling.
const char* knobAxisName(KnobAxis axis);
const char* buttonActionName(ButtonAction action);

struct EncoderConfig {
    unsigned lineA = 0;  // line offsets on the chip (KY-040: CLK = A, DT = B)
    unsigned lineB = 0;
    KnobAxis axis = KnobAxis::kAzimuth;
    double step = 1;  // degrees (azimuth, elevation) or metres (distance) per detent
    int stepsPerDetent = 4;
    bool reverse = false;  // swap the sense of rotation (A and B wired the other way round)
    AccelerationCurve acceleration;  // maxFactor 1 (the default): none
};

struct ButtonConfig {
    unsigned line = 0;
    ButtonAction action = ButtonAction::kNextPreset;
    bool activeLow = true;
    double debounceMs = 20;
};

struct KnobsConfig {
    bool enabled = false;
    std::string chip = "gpiochip0";  // a name, number or label (gpiod_chip_open_lookup) or a path
    std::string consumer = "vpe-player";  // the label the kernel shows for the requested lines
    std::vector<EncoderConfig> encoders;
    std::vector<ButtonConfig> buttons;
};

// Reads a board file's [gpio] table strictly: unknown keys, wrong types and bad values are
// refused with BoardConfigError, one line naming "file:gpio.encoder[1].axis: …" (array indices
// count from 0). `source` names the board file in errors.
KnobsConfig parseKnobsConfig(const toml::table& gpio, const std::string& source);

}  // namespace vpe::firmware::knobs
