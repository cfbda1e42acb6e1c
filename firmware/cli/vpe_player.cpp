// SPDX-License-Identifier: MIT
// vpe-player: the device program (firmware/README.md). Board file → Player (platform, bundle,
// renderer, light rig, event loop) → inputs (the board's hardware, or a replay) → frames until
// --frames, the replay's end, SIGTERM or SIGINT. With --scan, the same board's display and
// camera capture a structured-light scan instead (scan/scan_run.h); with a bus, the control
// page may ask the running player for one (scan/install_capture.h). Bad input: one line, exit
// status 2; a scan that cannot be completed: one line, exit status 1.
#include <iostream>
#include <string>
#include <vector>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/player/board_check.h"
#include "vpe/firmware/player/input_setup.h"
#include "vpe/firmware/player/player.h"
#include "vpe/firmware/player/player_log.h"
#include "vpe/firmware/player/player_options.h"
#include "vpe/firmware/scan/install_capture.h"
#include "vpe/firmware/scan/scan_run.h"
#include "vpe/proto/input_error.h"

namespace {

namespace fw = vpe::firmware;

int run(const fw::PlayerOptions& options, std::int64_t startNs) {
    const fw::BoardConfig board = fw::loadBoardConfig(options.board);
    if (options.scan) {
        const fw::ScanReport report = fw::runScan(options, board, startNs);
        std::cout << report.summaryLine() << "\n";
        if (options.json) {
            std::cout << report.json() << "\n";
        }
        return 0;
    }
    if (options.check) {
        std::cout << fw::checkBoard(board, options);  // throws PlayerInputError when bad
        return 0;
    }
    // Parse every input section before opening anything: a bad board file fails at once.
    const fw::InputSettings inputs = fw::readInputSettings(board);
    fw::Player player(options, board, startNs, fw::showClockFor(inputs));
    // The control page's install steps: a scan or a radiometric capture asked over the bus.
    if (vpe::firmware::bus::LightBus* bus = fw::addInputs(player, inputs, options)) {
        fw::acceptInstallCommands(player, *bus, board, options);
    }
    const fw::FrameReport report = player.run();
    std::cout << report.summaryLine() << "\n";
    if (options.json) {
        std::cout << report.json() << "\n";
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::int64_t startNs = fw::monotonicNowNs();
    try {
        const fw::PlayerOptions options =
            fw::parsePlayerOptions(std::vector<std::string>(argv + 1, argv + argc));
        if (options.help) {
            std::cout << fw::playerUsage();
            return 0;
        }
        return run(options, startNs);
    } catch (const vpe::proto::InputError& error) {
        // Usage, the board file, the bundle, a replay: one line naming the input.
        fw::playerLog(error.what());
        return 2;
    } catch (const std::exception& error) {
        fw::playerLog(error.what());
        return 1;
    }
}
