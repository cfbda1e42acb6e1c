// SPDX-License-Identifier: MIT
// The player's inputs from its board file: the [gpio] knobs, the [camera] lamp and the [osc]
// server, or, with --replay, the replay file decoded with those same settings; and the [bus]
// (the light shared with the other nodes of a show), with or without a replay. Hardware that is
// absent (no gpiochip, camera or free port, as on a CI machine) or a broker that cannot be
// reached is logged once, one line, and the player goes on with what it has.
#pragma once

#include <optional>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/bus/bus_config.h"
#include "vpe/firmware/bus/light_bus.h"
#include "vpe/firmware/knobs/knobs_config.h"
#include "vpe/firmware/osc/osc_config.h"
#include "vpe/firmware/osc/osc_dispatcher.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/player/player_options.h"
#include "vpe/firmware/tracking/camera_config.h"

namespace vpe::firmware {

struct InputSettings {
    std::optional<knobs::KnobsConfig> knobs;  // absent: no [gpio] section
    std::optional<CameraConfig> camera;
    std::optional<OscConfig> osc;
    std::optional<bus::BusConfig> bus;  // absent: no [bus] section
    // The board's [light] (the lamp's default distance for the camera model) and the board
    // file's name, for what is checked once the bundle is open.
    LightConfig light;
    std::string source;
};

// Parses the input sections. Throws BoardConfigError.
InputSettings readInputSettings(const BoardConfig& board);

// The light rig's clock: CLOCK_REALTIME when the bus is on (the nodes' shared clock), else
// CLOCK_MONOTONIC.
ShowClock showClockFor(const InputSettings& settings);

// OSC's ranges are the light rig's limits (with the distance range resolved from the bundle),
// so OSC refuses exactly what the rig would have to clamp.
OscLimits oscLimitsOf(const LightLimits& light);

// The lamp's map for `bundle` (lampDirectionMapOf: the board's table, or the bundle's camera
// on its light sphere). Throws BoardConfigError naming the board file's key.
LampDirectionMap lampDirectionFor(const CameraConfig& camera, const InputSettings& settings,
                                  const proto::BundleView& bundle);

// Adds the enabled inputs to the player (or the replay, with --replay). Throws
// PlayerInputError for a bad replay file, or an enabled camera with neither a table nor a
// bundle camera to map the lamp with (or a bundle camera of another aspect ratio). A lamp
// mapped by the bundle's camera follows the camera of each reloaded bundle. Returns the bus
// when one was added (borrowed: the player owns it), for the control page's install steps.
bus::LightBus* addInputs(Player& player, const InputSettings& settings,
                         const PlayerOptions& options);

}  // namespace vpe::firmware
