// SPDX-License-Identifier: MIT
// The `vpe` subcommands: each registers its options on the CLI11 app and returns the action
// to run once parsing succeeded.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace vpe::cli {

using Action = std::function<void()>;

void addFitCommand(CLI::App& app, Action& action);
void addEvalCommand(CLI::App& app, Action& action);
void addSweepCommand(CLI::App& app, Action& action);
void addNormalsCommand(CLI::App& app, Action& action);
void addSynthCommand(CLI::App& app, Action& action);
void addSegmentCommand(CLI::App& app, Action& action);
void addQuiltCommand(CLI::App& app, Action& action);
void addRelightCommand(CLI::App& app, Action& action);
void addExportRelightCommand(CLI::App& app, Action& action);
void addComposeCommand(CLI::App& app, Action& action);
void addWeightsCommand(CLI::App& app, Action& action);
void addQuiltQualityCommand(CLI::App& app, Action& action);
void addInfoCommand(CLI::App& app, Action& action);
void addBakeCommand(CLI::App& app, Action& action);
void addRenderCommand(CLI::App& app, Action& action);
void addTransferCommand(CLI::App& app, Action& action);
void addSynthProcamCommand(CLI::App& app, Action& action);
void addScanCommand(CLI::App& app, Action& action);
void addRadiometryCommand(CLI::App& app, Action& action);
void addCalibrateCommand(CLI::App& app, Action& action);
void addImportGrayCodeCommand(CLI::App& app, Action& action);
void addShowCheckCommand(CLI::App& app, Action& action);
void addProjectorRingCommand(CLI::App& app, Action& action);

// Prints a JSON object as the last thing on stdout.
void printJson(const std::string& json);

}  // namespace vpe::cli
