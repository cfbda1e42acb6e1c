// SPDX-License-Identifier: MIT
// The control page's install steps on a running player (proto/BUS.md, "Install steps";
// docs/control-page.md): a controller's command on vpe/<show>/command/<client id> asks this
// node for a scan or a radiometric capture with its board's [scan] section. The player lends
// its display (Player::lendDisplay: it stops drawing, the frame in flight done), the capture runs
// through runCapture — the code of vpe-player --scan — into [scan] out (default: "scan" beside
// the bundle), the player's bus, status and watchdog served between captures; its progress
// (at most 4 a second) and two small PNGs (the camera's view of the white pattern, the coverage
// map) go on vpe/<show>/install/<client id>/..., and the show resumes. A command while one runs
// is refused with one line.
#pragma once

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/bus/light_bus.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/player/player_options.h"

namespace vpe::firmware {

// Borrows `player` and `bus` for their lives (the bus is one of the player's inputs).
void acceptInstallCommands(Player& player, bus::LightBus& bus, const BoardConfig& board,
                           const PlayerOptions& options);

}  // namespace vpe::firmware
