// SPDX-License-Identifier: MIT
// parseKnobsConfig: reads a board file's [gpio] table (toml++) into a KnobsConfig, strictly:
// unknown keys, wrong types and bad values are refused with BoardConfigError, one line naming
// "file:gpio.encoder[1].axis: …" (array indices count from 0).
#pragma once

#include <string>

#include <toml++/toml.h>

#include "vpe/firmware/knobs/knobs_config.h"

namespace vpe::firmware::knobs {

// `gpio` is the [gpio] table; `source` names the board file in errors.
KnobsConfig parseKnobsConfig(const toml::table& gpio, const std::string& source);

}  // namespace vpe::firmware::knobs
