// SPDX-License-Identifier: MIT
// BoardSpec: the printed checkerboard a calibration photographs — squares along each side and
// their size — as `vpe calibrate --board 10x7:25mm` names it.
#pragma once

#include <string_view>

namespace vpe::calibrate {

struct BoardSpec {
    int squaresX = 10, squaresY = 7;
    double squareM = 0.025;

    // OpenCV's pattern size: the inner corners.
    int cornersX() const { return squaresX - 1; }
    int cornersY() const { return squaresY - 1; }
    int cornerCount() const { return cornersX() * cornersY(); }
    // Inner corner k (row by row from the first corner) on the board's plane z = 0, metres.
    double cornerX(int k) const { return (k % cornersX()) * squareM; }
    double cornerY(int k) const { return (k / cornersX()) * squareM; }
};

// "COLSxROWS:SIZE" with SIZE in mm (25mm), cm or m; squares 3..64 per side, different parities
// along the two sides not required (the corners' order is fixed by the squares' colours).
// Throws InputError "--board 'TEXT': problem".
BoardSpec parseBoardSpec(std::string_view text);

}  // namespace vpe::calibrate
