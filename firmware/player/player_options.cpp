// SPDX-License-Identifier: MIT
// PlayerOptions: vpe-player's argument parser.
#include "vpe/firmware/player/player_options.h"

#include <charconv>
#include <cstdlib>
#include <utility>

#include "vpe/firmware/board/board_config.h"

namespace vpe::firmware {

namespace {

long positive(const std::string& option, const std::string& text) {
    long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc{} || end != text.data() + text.size() || value < 1) {
        throw PlayerUsageError(option + ": expected a positive integer, got \"" + text + "\"");
    }
    return value;
}

}  // namespace

const char* playerUsage() {
    return "usage: vpe-player --board FILE --bundle FILE [--frames N] [--size WxH] [--rate HZ]\n"
           "                  [--out DIR] [--every K] [--preset NAME] [--replay EVENTS.jsonl]\n"
           "                  [--replay-loop] [--light-log FILE] [--json]\n"
           "       vpe-player --board FILE [--bundle FILE] --check\n"
           "       vpe-player --board FILE --scan OUT [--size WxH] [--json]\n"
           "  --frames N   stop after N frames (default: run until SIGTERM or SIGINT)\n"
           "  --rate HZ    headless frame rate (default: the board's render.rate; 0 = unpaced)\n"
           "  --replay F   feed recorded input events (firmware/README.md) through the decoders\n"
           "  --light-log F  one JSON line per frame: presentation time (CLOCK_REALTIME, us)\n"
           "               and the light drawn (to compare the nodes of a show)\n"
           "  --scan OUT   show the structured-light patterns, photograph each with the board's\n"
           "               camera ([scan], [camera]) and write the scan folder OUT\n"
           "  SIGHUP, or the bundle file being replaced, reloads the bundle\n";
}

PlayerOptions parsePlayerOptions(const std::vector<std::string>& arguments) {
    PlayerOptions options;
    for (std::size_t i = 0; i < arguments.size(); ++i) {
        const std::string& option = arguments[i];
        if (option == "--json") {
            options.json = true;
            continue;
        }
        if (option == "--check") {
            options.check = true;
            continue;
        }
        if (option == "--replay-loop") {
            options.replayLoop = true;
            continue;
        }
        if (option == "--help" || option == "-h") {
            options.help = true;
            continue;
        }
        if (option != "--board" && option != "--bundle" && option != "--frames" &&
            option != "--size" && option != "--out" && option != "--every" &&
            option != "--preset" && option != "--rate" && option != "--replay" &&
            option != "--scan" && option != "--light-log") {
            throw PlayerUsageError(option + ": unknown argument (see vpe-player --help)");
        }
        if (i + 1 >= arguments.size()) {
            throw PlayerUsageError(option + ": missing value");
        }
        const std::string& value = arguments[++i];
        if (option == "--board") {
            options.board = value;
        } else if (option == "--bundle") {
            options.bundle = value;
        } else if (option == "--frames") {
            options.frames = value == "0" ? 0 : positive(option, value);
        } else if (option == "--rate") {
            char* end = nullptr;
            const double rate = std::strtod(value.c_str(), &end);
            if (value.empty() || *end != '\0' || !(rate >= 0 && rate <= 1000)) {
                throw PlayerUsageError("--rate: expected frames per second in [0, 1000], got \"" +
                                       value + "\"");
            }
            options.rate = rate;
        } else if (option == "--replay") {
            options.replay = value;
        } else if (option == "--light-log") {
            if (value.empty()) {
                throw PlayerUsageError("--light-log: expected a file, got \"\"");
            }
            options.lightLog = value;
        } else if (option == "--scan") {
            if (value.empty()) {
                throw PlayerUsageError("--scan: expected a folder, got \"\"");
            }
            options.scan = value;
        } else if (option == "--every") {
            options.every = positive(option, value);
        } else if (option == "--size") {
            const std::optional<DisplayMode> size = parseDisplayMode(value);
            if (!size || size->refresh != 0) {
                throw PlayerUsageError("--size: expected WxH, got \"" + value + "\"");
            }
            options.width = size->width;
            options.height = size->height;
        } else if (option == "--out") {
            options.out = value;
        } else {
            options.preset = value;
        }
    }
    if (!options.help) {
        if (options.board.empty()) {
            throw PlayerUsageError("--board: missing (a board file such as boards/headless.toml)");
        }
        if (options.scan) {
            // A scan shows patterns, not a bundle: what plays a bundle does not apply.
            const std::vector<std::pair<bool, const char*>> playing{
                {!options.bundle.empty(), "--bundle"},
                {options.check, "--check"},
                {options.frames != 0, "--frames"},
                {options.out.has_value(), "--out"},
                {options.every != 1, "--every"},
                {!options.preset.empty(), "--preset"},
                {options.rate.has_value(), "--rate"},
                {options.replay.has_value(), "--replay"},
                {options.replayLoop, "--replay-loop"},
                {options.lightLog.has_value(), "--light-log"}};
            for (const auto& [given, name] : playing) {
                if (given) {
                    throw PlayerUsageError(std::string(name) +
                                           ": not used by --scan (which takes --board, --size "
                                           "and --json)");
                }
            }
        } else if (options.bundle.empty() && !options.check) {
            throw PlayerUsageError("--bundle: missing (a device bundle made by vpe bake)");
        }
    }
    return options;
}

}  // namespace vpe::firmware
