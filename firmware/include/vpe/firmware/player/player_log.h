// SPDX-License-Identifier: MIT
// playerLog: vpe-player's one way to say something: one line on stderr, "vpe-player: …" (the
// journal under systemd). Every part of the player logs through it.
#pragma once

#include <string>

namespace vpe::firmware {

void playerLog(const std::string& line);

}  // namespace vpe::firmware
