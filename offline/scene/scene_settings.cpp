// SPDX-License-Identifier: MIT
// Strict parsing of scene settings.
#include "vpe/scene/scene_settings.h"

#include <optional>
#include <string>
#include <vector>

#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::scene {

namespace {

// One or more finite numbers separated by commas; nothing else, no empty fields.
std::optional<std::vector<double>> parseList(std::string_view text) {
    std::vector<double> values;
    while (true) {
        const std::size_t comma = text.find(',');
        const auto value = text::parseNumber(text::trim(text.substr(0, comma)));
        if (!value) {
            return std::nullopt;
        }
        values.push_back(*value);
        if (comma == std::string_view::npos) {
            return values;
        }
        text.remove_prefix(comma + 1);
    }
}

std::string quoted(std::string_view what, std::string_view text) {
    return std::string(what) + ": '" + std::string(text) + "'";
}

// A grey value or r,g,b, each checked by `valid`.
template <typename Valid>
std::array<double, 3> parseColour(std::string_view text, std::string_view what, Valid valid,
                                  const char* range) {
    const auto values = parseList(text);
    if (!values || (values->size() != 1 && values->size() != 3)) {
        throw common::InputError(quoted(what, text) + " is not a value or r,g,b (numbers " + range +
                                 ")");
    }
    const std::array<double, 3> rgb =
        values->size() == 1 ? std::array<double, 3>{(*values)[0], (*values)[0], (*values)[0]}
                            : std::array<double, 3>{(*values)[0], (*values)[1], (*values)[2]};
    for (const double v : rgb) {
        if (!valid(v)) {
            throw common::InputError(quoted(what, text) + ": each value must be " + range);
        }
    }
    return rgb;
}

}  // namespace

std::array<double, 3> parseTriple(std::string_view text, std::string_view what) {
    const auto values = parseList(text);
    if (!values || values->size() != 3) {
        throw common::InputError(quoted(what, text) +
                                 " is not x,y,z (three finite numbers separated by commas)");
    }
    return {(*values)[0], (*values)[1], (*values)[2]};
}

proto::Vec3<double> parsePosition(std::string_view text, std::string_view what) {
    const auto xyz = parseTriple(text, what);
    return {xyz[0], xyz[1], xyz[2]};
}

std::array<double, 3> parseAlbedo(std::string_view text, std::string_view what) {
    return parseColour(
        text, what, [](double v) { return v > 0 && v <= 1; }, "in (0, 1]");
}

std::array<double, 3> parseAmbient(std::string_view text, std::string_view what) {
    return parseColour(
        text, what, [](double v) { return v >= 0; }, "≥ 0");
}

std::array<double, 3> parseBlackLevel(std::string_view text, std::string_view what) {
    return parseColour(
        text, what, [](double v) { return v >= 0 && v < 0.5; }, "in [0, 0.5)");
}

}  // namespace vpe::scene
