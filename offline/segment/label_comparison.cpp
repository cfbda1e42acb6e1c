// SPDX-License-Identifier: MIT
// Label maps compared by IoU after the best one-to-one matching.
#include "vpe/segment/label_comparison.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::segment {

std::vector<int> minimumCostAssignment(const std::vector<std::vector<double>>& cost) {
    // Kuhn–Munkres with row and column potentials, rows added one at a time (1-based inside).
    const int n = static_cast<int>(cost.size());
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> u(static_cast<std::size_t>(n) + 1, 0.0),
        v(static_cast<std::size_t>(n) + 1, 0.0);
    std::vector<int> rowOfColumn(static_cast<std::size_t>(n) + 1, 0),
        way(static_cast<std::size_t>(n) + 1, 0);
    for (int row = 1; row <= n; ++row) {
        rowOfColumn[0] = row;
        int column0 = 0;
        std::vector<double> minimum(static_cast<std::size_t>(n) + 1, inf);
        std::vector<char> used(static_cast<std::size_t>(n) + 1, 0);
        do {
            used[static_cast<std::size_t>(column0)] = 1;
            const int row0 = rowOfColumn[static_cast<std::size_t>(column0)];
            double delta = inf;
            int column1 = 0;
            for (int j = 1; j <= n; ++j) {
                const std::size_t sj = static_cast<std::size_t>(j);
                if (used[sj]) {
                    continue;
                }
                const double reduced = cost[static_cast<std::size_t>(row0 - 1)][sj - 1] -
                                       u[static_cast<std::size_t>(row0)] - v[sj];
                if (reduced < minimum[sj]) {
                    minimum[sj] = reduced;
                    way[sj] = column0;
                }
                if (minimum[sj] < delta) {
                    delta = minimum[sj];
                    column1 = j;
                }
            }
            for (int j = 0; j <= n; ++j) {
                const std::size_t sj = static_cast<std::size_t>(j);
                if (used[sj]) {
                    u[static_cast<std::size_t>(rowOfColumn[sj])] += delta;
                    v[sj] -= delta;
                } else {
                    minimum[sj] -= delta;
                }
            }
            column0 = column1;
        } while (rowOfColumn[static_cast<std::size_t>(column0)] != 0);
        do {
            const int column1 = way[static_cast<std::size_t>(column0)];
            rowOfColumn[static_cast<std::size_t>(column0)] =
                rowOfColumn[static_cast<std::size_t>(column1)];
            column0 = column1;
        } while (column0 != 0);
    }
    std::vector<int> columnOfRow(static_cast<std::size_t>(n), -1);
    for (int j = 1; j <= n; ++j) {
        if (rowOfColumn[static_cast<std::size_t>(j)] > 0) {
            columnOfRow[static_cast<std::size_t>(rowOfColumn[static_cast<std::size_t>(j)] - 1)] =
                j - 1;
        }
    }
    return columnOfRow;
}

LabelComparison compareLabels(const LabelMap& predicted, const LabelMap& truth) {
    if (predicted.width != truth.width || predicted.height != truth.height) {
        throw std::invalid_argument("compareLabels: sizes differ");
    }
    constexpr std::size_t kValues = 256;
    std::vector<std::size_t> joint(kValues * kValues, 0), truthArea(kValues, 0),
        predictedArea(kValues, 0);
    LabelComparison result;
    for (std::size_t p = 0; p < truth.values.size(); ++p) {
        const std::uint8_t t = truth.values[p], q = predicted.values[p];
        if (t == LabelMap::kNoLabel || q == LabelMap::kNoLabel) {
            continue;
        }
        ++joint[t * kValues + q];
        ++truthArea[t];
        ++predictedArea[q];
        ++result.comparedPixels;
    }
    std::vector<int> predictedLabels;
    for (int label = 0; label < static_cast<int>(kValues); ++label) {
        if (truthArea[static_cast<std::size_t>(label)] > 0) {
            result.truthLabels.push_back(label);
        }
        if (predictedArea[static_cast<std::size_t>(label)] > 0) {
            predictedLabels.push_back(label);
        }
    }
    if (result.truthLabels.empty()) {
        return result;
    }
    auto iouOf = [&](int t, int q) {
        const std::size_t both =
            joint[static_cast<std::size_t>(t) * kValues + static_cast<std::size_t>(q)];
        const std::size_t either = truthArea[static_cast<std::size_t>(t)] +
                                   predictedArea[static_cast<std::size_t>(q)] - both;
        return either > 0 ? static_cast<double>(both) / static_cast<double>(either) : 0.0;
    };
    // Square cost 1 − IoU; padding rows or columns (more labels on one side) cost 1.
    const std::size_t n = std::max(result.truthLabels.size(), predictedLabels.size());
    std::vector<std::vector<double>> cost(n, std::vector<double>(n, 1.0));
    for (std::size_t i = 0; i < result.truthLabels.size(); ++i) {
        for (std::size_t j = 0; j < predictedLabels.size(); ++j) {
            cost[i][j] = 1.0 - iouOf(result.truthLabels[i], predictedLabels[j]);
        }
    }
    const std::vector<int> assignment = minimumCostAssignment(cost);
    double sum = 0;
    for (std::size_t i = 0; i < result.truthLabels.size(); ++i) {
        const int j = assignment[i];
        const bool matched = j >= 0 && static_cast<std::size_t>(j) < predictedLabels.size();
        const int label = matched ? predictedLabels[static_cast<std::size_t>(j)] : -1;
        const double iou = matched ? iouOf(result.truthLabels[i], label) : 0.0;
        result.matchedLabels.push_back(iou > 0 ? label : -1);
        result.iou.push_back(iou);
        sum += iou;
    }
    result.meanIou = sum / static_cast<double>(result.truthLabels.size());
    return result;
}

}  // namespace vpe::segment
