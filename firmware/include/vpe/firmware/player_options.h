// SPDX-License-Identifier: MIT
// PlayerOptions: vpe-player's command line, parsed without a library (the device build has
// none): bad arguments throw PlayerUsageError with one line.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vpe::firmware {

class PlayerUsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct PlayerOptions {
    std::filesystem::path board;
    std::filesystem::path bundle;
    long frames = 120;
    std::optional<int> width, height;  // --size WxH (headless render target)
    std::optional<std::filesystem::path> out;
    long every = 1;      // with --out: write frames 0, k, 2k, …
    std::string preset;  // empty: the bundle's first
    bool json = false;
    bool help = false;
};

const char* playerUsage();

// arguments: argv[1 …]. Throws PlayerUsageError ("--frames: expected a positive integer, got x").
PlayerOptions parsePlayerOptions(const std::vector<std::string>& arguments);

}  // namespace vpe::firmware
