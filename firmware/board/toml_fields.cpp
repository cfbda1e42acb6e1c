// SPDX-License-Identifier: MIT
#include "board/toml_fields.h"

#include <cmath>
#include <cstdio>
#include <vector>

namespace vpe::firmware::toml_fields {

void fail(const std::string& source, const std::string& key, const std::string& problem) {
    throw BoardConfigError(source + ":" + key + ": " + problem);
}

std::string qualified(const std::string& section, const std::string& key) {
    return section.empty() ? key : section + "." + key;
}

std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

const char* typeName(const toml::node& node) {
    switch (node.type()) {
        case toml::node_type::table:
            return "a table";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::string:
            return "a string";
        case toml::node_type::integer:
            return "an integer";
        case toml::node_type::floating_point:
            return "a number";
        case toml::node_type::boolean:
            return "a boolean";
        default:
            return "a date or time";
    }
}

void checkKeys(const toml::table& table, const std::string& source, const std::string& section,
               const KeySet& allowed) {
    for (const auto& [key, node] : table) {
        (void)node;
        const std::string name(key.str());
        if (!allowed.contains(name)) {
            std::string list;
            for (const std::string& a : allowed) {
                list += (list.empty() ? "" : ", ") + a;
            }
            fail(source, qualified(section, name), "unknown key (known: " + list + ")");
        }
    }
}

std::optional<std::string> optionalString(const toml::table& table, const std::string& source,
                                          const std::string& section, const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return std::nullopt;
    }
    if (!node->is_string()) {
        fail(source, qualified(section, key),
             std::string("expected a string, got ") + typeName(*node));
    }
    return *node->value<std::string>();
}

namespace {

double numberOf(const toml::node& node, const std::string& source, const std::string& key) {
    if (!node.is_number()) {
        fail(source, key, std::string("expected a number, got ") + typeName(node));
    }
    const double value = *node.value<double>();
    if (!std::isfinite(value)) {
        fail(source, key, "expected a finite number");
    }
    return value;
}

}  // namespace

std::optional<double> optionalNumber(const toml::table& table, const std::string& source,
                                     const std::string& section, const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return std::nullopt;
    }
    return numberOf(*node, source, qualified(section, key));
}

std::optional<long long> optionalInteger(const toml::table& table, const std::string& source,
                                         const std::string& section, const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return std::nullopt;
    }
    if (!node->is_integer()) {
        fail(source, qualified(section, key),
             std::string("expected an integer, got ") + typeName(*node));
    }
    return *node->value<long long>();
}

std::optional<bool> optionalBool(const toml::table& table, const std::string& source,
                                 const std::string& section, const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return std::nullopt;
    }
    if (!node->is_boolean()) {
        fail(source, qualified(section, key),
             std::string("expected a boolean, got ") + typeName(*node));
    }
    return *node->value<bool>();
}

int integerIn(const toml::table& table, const std::string& source, const std::string& section,
              const char* key, long long low, long long high, int fallback) {
    const std::optional<long long> value = optionalInteger(table, source, section, key);
    if (!value) {
        return fallback;
    }
    if (*value < low || *value > high) {
        fail(source, qualified(section, key),
             "expected an integer in " + std::to_string(low) + "…" + std::to_string(high) +
                 ", got " + std::to_string(*value));
    }
    return static_cast<int>(*value);
}

double numberIn(const toml::table& table, const std::string& source, const std::string& section,
                const char* key, double low, bool lowOpen, double high, double fallback) {
    const std::optional<double> value = optionalNumber(table, source, section, key);
    if (!value) {
        return fallback;
    }
    if ((lowOpen ? !(*value > low) : !(*value >= low)) || !(*value <= high)) {
        fail(source, qualified(section, key),
             std::string("expected a number in ") + (lowOpen ? "(" : "[") + numberText(low) + ", " +
                 numberText(high) + "], got " + numberText(*value));
    }
    return *value;
}

std::optional<std::pair<double, double>> optionalRange(const toml::table& table,
                                                       const std::string& source,
                                                       const std::string& section,
                                                       const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return std::nullopt;
    }
    const std::string name = qualified(section, key);
    const toml::array* array = node->as_array();
    if (array == nullptr || array->size() != 2) {
        fail(source, name, std::string("expected [low, high], got ") + typeName(*node));
    }
    const double low = numberOf(*array->get(0), source, name);
    const double high = numberOf(*array->get(1), source, name);
    if (low > high) {
        fail(source, name, "low is above high");
    }
    return std::pair{low, high};
}

const toml::table* optionalTable(const toml::table& table, const std::string& source,
                                 const std::string& section, const char* key) {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return nullptr;
    }
    if (!node->is_table()) {
        fail(source, qualified(section, key),
             std::string("expected a table, got ") + typeName(*node));
    }
    return node->as_table();
}

std::vector<const toml::table*> optionalTableArray(const toml::table& table,
                                                   const std::string& source,
                                                   const std::string& section, const char* key) {
    std::vector<const toml::table*> tables;
    const toml::node* node = table.get(key);
    if (node == nullptr) {
        return tables;
    }
    const toml::array* array = node->as_array();
    if (array == nullptr || !array->is_array_of_tables()) {
        fail(source, qualified(section, key),
             std::string("expected an array of tables ([[") + qualified(section, key) +
                 "]]), got " + typeName(*node));
    }
    for (const toml::node& element : *array) {
        tables.push_back(element.as_table());
    }
    return tables;
}

}  // namespace vpe::firmware::toml_fields
