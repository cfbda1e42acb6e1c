// SPDX-License-Identifier: MIT
// InputError: bad input (a file, a line of it, a value, an option), in one line that names
// the input. The base of every bad-input error on both sides; each program maps it to that
// one line on stderr and exit status 2, in one place.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace vpe::proto {

class InputError : public std::runtime_error {
public:
    // A message that already names its input: "scene.vpeb: checksum mismatch".
    explicit InputError(const std::string& message)
        : std::runtime_error(message), problem_(message) {}
    // "INPUT: PROBLEM".
    InputError(const std::filesystem::path& input, const std::string& problem)
        : std::runtime_error(input.string() + ": " + problem),
          input_(input.string()),
          problem_(problem) {}
    // "INPUT:LINE: PROBLEM".
    InputError(const std::filesystem::path& input, int line, const std::string& problem)
        : std::runtime_error(input.string() + ":" + std::to_string(line) + ": " + problem),
          input_(input.string() + ":" + std::to_string(line)),
          problem_(problem) {}

    // The input, when it was given apart from the problem; empty otherwise.
    const std::string& input() const { return input_; }
    // What is wrong, without the input (the whole message when it was given as one).
    const std::string& problem() const { return problem_; }

private:
    std::string input_;
    std::string problem_;
};

}  // namespace vpe::proto
