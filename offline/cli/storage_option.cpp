// SPDX-License-Identifier: MIT
// --storage half|float.
#include "cli/storage_option.h"

namespace vpe::cli {

void addStorageOption(CLI::App* command, std::string& value, const std::string& whenOmitted) {
    command
        ->add_option("--storage", value,
                     "Model file channels: half (16-bit float, relative error <= 4.9e-4, "
                     "docs/model-file.md) or float (exact); default: " +
                         whenOmitted)
        ->check(CLI::IsMember({"half", "float"}));
}

std::optional<model::ModelStorage> parseStorage(const std::string& value) {
    if (value.empty()) {
        return std::nullopt;
    }
    return value == "half" ? model::ModelStorage::kHalf : model::ModelStorage::kFloat;
}

}  // namespace vpe::cli
