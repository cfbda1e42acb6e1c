// SPDX-License-Identifier: MIT
// Strict reading of board-file tables (toml++), shared by every section's parser: unknown keys
// and wrong types are refused with BoardConfigError, one line naming "file:section.key".
// Private to firmware/ (toml++ stays out of the public headers).
#pragma once

#include <optional>
#include <set>
#include <string>
#include <utility>

#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

namespace vpe::firmware::toml_fields {

using KeySet = std::set<std::string, std::less<>>;

// Throws BoardConfigError("source:key: problem").
[[noreturn]] void fail(const std::string& source, const std::string& key,
                       const std::string& problem);

// "a table", "a string", "an integer", …: for "expected X, got Y".
const char* typeName(const toml::node& node);

// `table` (the section named `section`, "" for the root) holds only `allowed` keys.
void checkKeys(const toml::table& table, const std::string& source, const std::string& section,
               const KeySet& allowed);

// Each returns nullopt when the key is absent and fails on a wrong type. Numbers accept
// integers too; integers refuse fractions.
std::optional<std::string> optionalString(const toml::table& table, const std::string& source,
                                          const std::string& section, const char* key);
std::optional<double> optionalNumber(const toml::table& table, const std::string& source,
                                     const std::string& section, const char* key);
std::optional<long long> optionalInteger(const toml::table& table, const std::string& source,
                                         const std::string& section, const char* key);
std::optional<bool> optionalBool(const toml::table& table, const std::string& source,
                                 const std::string& section, const char* key);
// An integer in [low, high]; `fallback` when absent.
int integerIn(const toml::table& table, const std::string& source, const std::string& section,
              const char* key, long long low, long long high, int fallback);
// A number in [low, high] ((low, high] when `lowOpen`); `fallback` when absent.
double numberIn(const toml::table& table, const std::string& source, const std::string& section,
                const char* key, double low, bool lowOpen, double high, double fallback);
// [low, high] with low ≤ high, both finite.
std::optional<std::pair<double, double>> optionalRange(const toml::table& table,
                                                       const std::string& source,
                                                       const std::string& section, const char* key);
// A sub-table (nullptr when absent) or an array of tables (empty when absent).
const toml::table* optionalTable(const toml::table& table, const std::string& source,
                                 const std::string& section, const char* key);
std::vector<const toml::table*> optionalTableArray(const toml::table& table,
                                                   const std::string& source,
                                                   const std::string& section, const char* key);

// "section.key", or "key" for the root.
std::string qualified(const std::string& section, const std::string& key);

// "%g": errors quote 0.5 as 0.5, the way the file most likely wrote it.
std::string numberText(double value);

}  // namespace vpe::firmware::toml_fields
