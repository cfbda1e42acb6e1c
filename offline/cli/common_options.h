// SPDX-License-Identifier: MIT
// Options most subcommands share, worded the same everywhere.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace vpe::cli {

// --threads N: worker threads (0: all cores).
void addThreadsOption(CLI::App* command, int& threads);

// --json: end stdout with a JSON report (printJson).
void addJsonFlag(CLI::App* command, bool& json);

// --held-out N: the RTI benchmarks' every N-th light (N from 2); `description` says what the
// command does with those lights.
void addHeldOutOption(CLI::App* command, int& heldOut, const std::string& description);

// An option whose value is one of `choices` (its default shown in --help).
void addChoiceOption(CLI::App* command, const std::string& name, std::string& value,
                     const std::string& description, const std::vector<std::string>& choices);

// --mesh-scale: metres per unit of the screen object's mesh file.
void addMeshScaleOption(CLI::App* command, double& metresPerUnit);

// --calibration-unit m|cm|mm: the unit of a calibration file's T when the file does not say
// (procam-calibration's is its chessboard squares'); empty when not given.
void addCalibrationUnitOption(CLI::App* command, std::string& unit);

}  // namespace vpe::cli
