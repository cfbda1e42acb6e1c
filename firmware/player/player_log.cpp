// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/player_log.h"

#include <iostream>

namespace vpe::firmware {

void playerLog(const std::string& line) {
    std::cerr << "vpe-player: " << line << "\n";
}

}  // namespace vpe::firmware
