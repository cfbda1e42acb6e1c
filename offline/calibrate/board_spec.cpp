// SPDX-License-Identifier: MIT
// Parsing --board COLSxROWS:SIZE.
#include "vpe/calibrate/board_spec.h"

#include <charconv>
#include <cmath>
#include <string>

#include "vpe/common/input_error.h"

namespace vpe::calibrate {

BoardSpec parseBoardSpec(std::string_view text) {
    const auto fail = [&](const std::string& problem) {
        return common::InputError("--board '" + std::string(text) + "': " + problem);
    };
    const std::size_t times = text.find('x');
    const std::size_t colon = text.find(':');
    if (times == std::string_view::npos || colon == std::string_view::npos || colon < times) {
        throw fail("expected COLSxROWS:SIZE, e.g. 10x7:25mm (squares, not inner corners)");
    }
    BoardSpec board;
    const auto integer = [&](std::string_view part, int& value) {
        const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
        if (error != std::errc() || end != part.data() + part.size() || value < 3 || value > 64) {
            throw fail("squares along a side must be a whole number in 3..64");
        }
    };
    integer(text.substr(0, times), board.squaresX);
    integer(text.substr(times + 1, colon - times - 1), board.squaresY);
    std::string_view size = text.substr(colon + 1);
    double scale = 0;
    for (const auto& [suffix, metres] : {std::pair{"mm", 0.001}, {"cm", 0.01}, {"m", 1.0}}) {
        if (size.ends_with(suffix)) {
            size.remove_suffix(std::string_view(suffix).size());
            scale = metres;
            break;
        }
    }
    if (scale == 0) {
        throw fail("give the square's size with its unit: mm, cm or m");
    }
    double value = 0;
    const auto [end, error] = std::from_chars(size.data(), size.data() + size.size(), value);
    if (error != std::errc() || end != size.data() + size.size() || !(value > 0) ||
        !std::isfinite(value)) {
        throw fail("the square's size must be a positive number");
    }
    board.squareM = value * scale;
    if (board.squareM < 1e-3 || board.squareM > 1.0) {
        throw fail("a square of " + std::to_string(board.squareM * 1000) +
                   " mm is outside 1 mm .. 1 m");
    }
    return board;
}

}  // namespace vpe::calibrate
