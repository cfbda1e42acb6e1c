// SPDX-License-Identifier: MIT
// --storage half|float: the channel type of the model files a command writes.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "vpe/model/fourier_model_file.h"

namespace vpe::cli {

// Adds --storage to `command`, stored as text in `value` ("" when not given).
void addStorageOption(CLI::App* command, std::string& value, const std::string& whenOmitted);

// The storage `value` names, or nullopt when it is empty (the command's default applies).
std::optional<model::ModelStorage> parseStorage(const std::string& value);

}  // namespace vpe::cli
