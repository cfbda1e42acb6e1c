// SPDX-License-Identifier: MIT
// InputError: bad input from the user (a file, a line of it, a value), reported in one line
// that names the input. The `vpe` command turns it into exit status 2.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace vpe::common {

class InputError : public std::runtime_error {
public:
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
    InputError(const std::filesystem::path& input, const std::string& problem)
        : std::runtime_error(input.string() + ": " + problem) {}
    InputError(const std::filesystem::path& input, int line, const std::string& problem)
        : std::runtime_error(input.string() + ":" + std::to_string(line) + ": " + problem) {}
};

}  // namespace vpe::common
