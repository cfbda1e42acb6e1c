// SPDX-License-Identifier: MIT
// vpe_write_scan_installation FOLDER: the scan tests' small simulated installation (a ball
// before a wall, a 320 × 180 projector, a 320 × 240 camera; tests/firmware/scan_installation.h)
// written into FOLDER as installation.toml and ball-wall.obj, for the control page's scenario,
// whose nodes scan it with [scan] simulate.
#include <filesystem>
#include <iostream>

#include "scan_installation.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: vpe_write_scan_installation FOLDER\n";
        return 2;
    }
    try {
        std::filesystem::create_directories(argv[1]);
        const auto installation = vpe::firmware::testing::writeScanInstallation(argv[1]);
        std::cout << installation.sceneFile.string() << "\n";
    } catch (const std::exception& error) {
        std::cerr << "vpe_write_scan_installation: " << error.what() << "\n";
        return 1;
    }
    return 0;
}
