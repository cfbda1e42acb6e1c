// SPDX-License-Identifier: MIT
// How well a segmentation matches a reference: labels are arbitrary numbers, so predicted
// labels are first matched one-to-one to reference labels (the matching that maximizes the
// summed IoU, by the Hungarian method), then the IoU of each reference label is reported.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/segment/label_map.h"

namespace vpe::segment {

struct LabelComparison {
    std::vector<int> truthLabels;    // the reference labels present, ascending
    std::vector<int> matchedLabels;  // predicted label per reference label; −1: none left
    std::vector<double> iou;         // per reference label; 0 when unmatched
    double meanIou = 0;              // over the reference labels
    std::size_t comparedPixels = 0;  // labelled in both
};

// Compares over the pixels labelled in both maps (same size required).
LabelComparison compareLabels(const LabelMap& predicted, const LabelMap& truth);

// The assignment of rows to columns of a square cost matrix with the least total cost
// (Hungarian method with potentials, O(n³)). Returns the column of each row.
std::vector<int> minimumCostAssignment(const std::vector<std::vector<double>>& cost);

}  // namespace vpe::segment
