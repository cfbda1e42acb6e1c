// SPDX-License-Identifier: MIT
// `vpe-player --board F [--bundle B] --check`: parses every section of the board file (the
// same parsers the player uses), fits the camera calibration, says which devices are present
// on this machine, and, given a bundle, opens it (checksum verified) and compares its
// projector size with the display's. A report on stdout; any error is a PlayerInputError (one
// line, exit status 2). Absent devices are not errors: the player runs without them.
#pragma once

#include <string>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/player/player_options.h"

namespace vpe::firmware {

std::string checkBoard(const BoardConfig& board, const PlayerOptions& options);

}  // namespace vpe::firmware
