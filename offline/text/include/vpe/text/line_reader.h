// SPDX-License-Identifier: MIT
// Splitting text input into lines and fields, tolerant of CRLF, tabs, trailing blanks and a
// UTF-8 byte-order mark, and strict, locale-independent number parsing.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vpe::text {

struct Line {
    int number;             // 1-based
    std::string_view text;  // without the line ending, trimmed of surrounding blanks
};

// The whole file; throws InputError "PATH: cannot open WHAT" when it cannot be read.
std::string readTextFile(const std::filesystem::path& path, std::string_view what);

std::vector<Line> splitLines(std::string_view text);
std::vector<std::string_view> splitFields(std::string_view line);
std::string_view trim(std::string_view text);

// The whole field must be a finite number.
std::optional<double> parseNumber(std::string_view field);
std::optional<long> parseInteger(std::string_view field);

}  // namespace vpe::text
