// SPDX-License-Identifier: MIT
// PlayerOptions: vpe-player's command line, parsed without a library (the device build has
// none): bad arguments throw PlayerUsageError with one line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/input_error.h"

namespace vpe::firmware {

class PlayerUsageError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

struct PlayerOptions {
    std::filesystem::path board;
    std::filesystem::path bundle;
    long frames = 0;  // 0: until SIGTERM/SIGINT (the gallery); N: stop after N frames
    std::optional<int> width, height;  // --size WxH (headless render target)
    std::optional<std::filesystem::path> out;
    long every = 1;              // with --out: write frames 0, k, 2k, …
    std::string preset;          // empty: the bundle's first
    std::optional<double> rate;  // --rate HZ: overrides the board's render.rate (headless)
    std::optional<std::filesystem::path> replay;  // --replay events.jsonl
    bool replayLoop = false;                      // --replay-loop: start the file over when it ends
    // --light-log FILE: one JSON line per frame tick, the presentation time on CLOCK_REALTIME
    // and the light drawn for it (player/light_log.h).
    std::optional<std::filesystem::path> lightLog;
    bool check = false;  // --check: validate the board file (and bundle, if given), exit
    // --scan OUT: show the structured-light patterns and photograph them into the folder OUT
    // (firmware/README.md, "Scanning"); no bundle.
    std::optional<std::filesystem::path> scan;
    bool json = false;
    bool help = false;
};

const char* playerUsage();

// arguments: argv[1 …]. --bundle is optional with --check and refused with --scan, which takes
// only --board, --size and --json. Throws PlayerUsageError ("--frames: expected a positive
// integer, got x").
PlayerOptions parsePlayerOptions(const std::vector<std::string>& arguments);

}  // namespace vpe::firmware
