// SPDX-License-Identifier: MIT
// Options most subcommands share.
#include "cli/common_options.h"

namespace vpe::cli {

void addThreadsOption(CLI::App* command, int& threads) {
    command->add_option("--threads", threads, "Worker threads (0: all cores)")
        ->capture_default_str();
}

void addJsonFlag(CLI::App* command, bool& json) {
    command->add_flag("--json", json, "End stdout with a JSON report");
}

void addHeldOutOption(CLI::App* command, int& heldOut, const std::string& description) {
    command->add_option("--held-out", heldOut, description)->check(CLI::Range(2, 1000));
}

void addChoiceOption(CLI::App* command, const std::string& name, std::string& value,
                     const std::string& description, const std::vector<std::string>& choices) {
    command->add_option(name, value, description)
        ->check(CLI::IsMember(choices))
        ->capture_default_str();
}

void addMeshScaleOption(CLI::App* command, double& metresPerUnit) {
    command
        ->add_option("--mesh-scale", metresPerUnit, "Metres per mesh unit (0.001 for millimetres)")
        ->capture_default_str();
}

void addCalibrationUnitOption(CLI::App* command, std::string& unit) {
    command
        ->add_option("--calibration-unit", unit,
                     "The unit of the calibration's translation when the file does not say "
                     "(procam-calibration's: its chessboard squares', usually mm)")
        ->check(CLI::IsMember({"m", "cm", "mm"}));
}

}  // namespace vpe::cli
