// SPDX-License-Identifier: MIT
// The macro shape (local quadratic regression of the normals) and detail normal maps.
#include "vpe/normals/detail_normals.h"

#include <algorithm>
#include <cmath>
#include <variant>

#include <Eigen/Dense>

#include "vpe/proto/detail_normal.h"

namespace vpe::normals {

namespace {

// The window's σ on the grid the regression runs on: the normals are averaged over blocks of
// f × f pixels first, f = ⌊σ / kGridSigma⌋, so that the cost does not grow with σ² (a 2048²
// capture's σ = 256 px becomes 8 cells of 256² blocks); the macro shape is smooth at that scale.
constexpr double kGridSigma = 8.0;

// A grid of weighted normal sums (weight: how many valid normals a cell holds).
struct WeightedGrid {
    int width = 0, height = 0;
    std::vector<double> weight;  // per cell
    std::vector<double> sum;     // 3 per cell
};

// Per cell, the quadratic in (dx, dy)/σ that best fits the cells' mean normals under a
// Gaussian window of σ cells weighted by the cells' weights, evaluated at the cell, normalized;
// valid where the window holds any weight. Separable: a horizontal pass of the moments
// Σ g(dx)·(dx/σ)^p·{w, w·n}, then per cell the vertical pass and a 6 × 6 solve.
NormalMap quadraticRegression(const WeightedGrid& grid, double sigma) {
    const int width = grid.width, height = grid.height;
    const std::size_t cells = static_cast<std::size_t>(width) * height;
    const int radius = std::max(1, static_cast<int>(std::ceil(3.0 * sigma)));
    std::vector<double> g(2 * static_cast<std::size_t>(radius) + 1);
    for (int k = -radius; k <= radius; ++k) {
        g[static_cast<std::size_t>(k + radius)] = std::exp(-0.5 * k * k / (sigma * sigma));
    }
    // Planes: Σ g·d^p·w for p ≤ 4, then Σ g·d^p·w·n_a for a = x, y, z and p ≤ 2.
    constexpr int kPlanes = 5 + 3 * 3;
    const auto planeOf = [](int a, int p) { return a == 0 ? p : 5 + 3 * (a - 1) + p; };
    std::vector<double> horizontal(cells * kPlanes, 0.0);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            double* out = horizontal.data() + (static_cast<std::size_t>(y) * width + x) * kPlanes;
            for (int k = std::max(-radius, -x); k <= std::min(radius, width - 1 - x); ++k) {
                const std::size_t i = static_cast<std::size_t>(y) * width + x + k;
                if (!(grid.weight[i] > 0)) {
                    continue;
                }
                const double d = k / sigma;
                double power = g[static_cast<std::size_t>(k + radius)];
                for (int p = 0; p <= 4; ++p, power *= d) {
                    out[planeOf(0, p)] += power * grid.weight[i];
                    if (p <= 2) {
                        for (int a = 1; a <= 3; ++a) {
                            out[planeOf(a, p)] += power * grid.sum[i * 3 + a - 1];
                        }
                    }
                }
            }
        }
    }
    // The basis (1, dx, dy, dx², dx·dy, dy²) as powers (p, q).
    constexpr int kP[6] = {0, 1, 0, 2, 1, 0}, kQ[6] = {0, 0, 1, 0, 1, 2};
    NormalMap out;
    out.resize(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            double S[5][5] = {}, T[3][3][3] = {};
            for (int k = std::max(-radius, -y); k <= std::min(radius, height - 1 - y); ++k) {
                const double* in =
                    horizontal.data() + (static_cast<std::size_t>(y + k) * width + x) * kPlanes;
                const double d = k / sigma;
                double power = g[static_cast<std::size_t>(k + radius)];
                for (int q = 0; q <= 4; ++q, power *= d) {
                    for (int p = 0; p + q <= 4; ++p) {
                        S[p][q] += power * in[planeOf(0, p)];
                    }
                    for (int a = 0; a < 3; ++a) {
                        for (int p = 0; p + q <= 2; ++p) {
                            T[a][p][q] += power * in[planeOf(a + 1, p)];
                        }
                    }
                }
            }
            if (!(S[0][0] > 0)) {
                continue;
            }
            Eigen::Matrix<double, 6, 6> A;
            Eigen::Matrix<double, 6, 3> b;
            for (int i = 0; i < 6; ++i) {
                for (int j = 0; j < 6; ++j) {
                    A(i, j) = S[kP[i] + kP[j]][kQ[i] + kQ[j]];
                }
                for (int a = 0; a < 3; ++a) {
                    b(i, a) = T[a][kP[i]][kQ[i]];
                }
            }
            // A little ridge on the slopes and curvatures: where the window holds few normals
            // (an edge, a hole) the fit leans toward the plain weighted mean instead of
            // extrapolating.
            A.diagonal().tail<5>().array() += 1e-6 * A(0, 0);
            const Eigen::Matrix<double, 6, 3> beta = A.ldlt().solve(b);
            proto::Vec3d m{beta(0, 0), beta(0, 1), beta(0, 2)};
            double length = std::sqrt(proto::dot(m, m));
            if (!(length > 1e-6) || !std::isfinite(length)) {
                m = {b(0, 0), b(0, 1), b(0, 2)};  // the plain weighted mean
                length = std::sqrt(proto::dot(m, m));
                if (!(length > 0)) {
                    continue;
                }
            }
            const std::size_t o = static_cast<std::size_t>(y) * width + x;
            out.xyz[o * 3] = static_cast<float>(m.x / length);
            out.xyz[o * 3 + 1] = static_cast<float>(m.y / length);
            out.xyz[o * 3 + 2] = static_cast<float>(m.z / length);
            out.valid[o] = 1;
        }
    }
    return out;
}

}  // namespace

double defaultMacroSigma(int width, int height) {
    return kMacroSigmaShare * static_cast<double>(std::max(width, height));
}

NormalMap lowPassNormals(const NormalMap& normals, double sigma) {
    const int width = normals.width, height = normals.height;
    const int block = std::max(1, static_cast<int>(std::floor(sigma / kGridSigma)));
    WeightedGrid grid;
    grid.width = (width + block - 1) / block;
    grid.height = (height + block - 1) / block;
    grid.weight.assign(static_cast<std::size_t>(grid.width) * grid.height, 0.0);
    grid.sum.assign(grid.weight.size() * 3, 0.0);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = normals.index(x, y);
            if (!normals.valid[p]) {
                continue;
            }
            const std::size_t c = static_cast<std::size_t>(y / block) * grid.width + x / block;
            grid.weight[c] += 1.0;
            for (int a = 0; a < 3; ++a) {
                grid.sum[c * 3 + a] += static_cast<double>(normals.xyz[p * 3 + a]);
            }
        }
    }
    const NormalMap coarse = quadraticRegression(grid, std::max(sigma / block, 0.5));
    if (block == 1) {
        NormalMap out = coarse;
        out.valid = normals.valid;
        for (std::size_t p = 0; p < out.valid.size(); ++p) {
            out.valid[p] = out.valid[p] && coarse.valid[p];
        }
        return out;
    }
    // Back to the pixels: bilinear between the cell centres (clamped to the grid), over the
    // valid cells, renormalized.
    NormalMap out;
    out.resize(width, height);
    for (int y = 0; y < height; ++y) {
        const double cy = std::clamp((y + 0.5) / block - 0.5, 0.0, grid.height - 1.0);
        const int y0 = static_cast<int>(cy), y1 = std::min(y0 + 1, grid.height - 1);
        const double fy = cy - y0;
        for (int x = 0; x < width; ++x) {
            const std::size_t p = normals.index(x, y);
            if (!normals.valid[p]) {
                continue;
            }
            const double cx = std::clamp((x + 0.5) / block - 0.5, 0.0, grid.width - 1.0);
            const int x0 = static_cast<int>(cx), x1 = std::min(x0 + 1, grid.width - 1);
            const double fx = cx - x0;
            proto::Vec3d m{0, 0, 0};
            const int xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
            const double ws[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
            for (int i = 0; i < 4; ++i) {
                const proto::Vec3d c = coarse.at(xs[i], ys[i]);
                const double w = coarse.validAt(xs[i], ys[i]) ? ws[i] : 0.0;
                m = {m.x + w * c.x, m.y + w * c.y, m.z + w * c.z};
            }
            const double length = std::sqrt(proto::dot(m, m));
            if (!(length > 0)) {
                continue;
            }
            out.xyz[p * 3] = static_cast<float>(m.x / length);
            out.xyz[p * 3 + 1] = static_cast<float>(m.y / length);
            out.xyz[p * 3 + 2] = static_cast<float>(m.z / length);
            out.valid[p] = 1;
        }
    }
    return out;
}

proto::Vec3d imageRightDirection(const capture::Capture& capture) {
    if (const auto* pinhole = std::get_if<capture::PinholeCamera>(&capture.camera)) {
        // World → camera is R (x right, y down): the camera's x axis is R's first row.
        const auto& r = pinhole->rotation;
        return proto::normalized(proto::Vec3d{r[0], r[1], r[2]});
    }
    return {1, 0, 0};  // orthographic: world = camera frame
}

proto::Vec3d detailNormalOf(const proto::Vec3d& normal, const proto::Vec3d& macroNormal,
                            const proto::Vec3d& imageRight) {
    const proto::Vec3d up = cross(macroNormal, imageRight);
    return proto::detailNormalIn(proto::tangentFrame(macroNormal, imageRight, up), normal);
}

}  // namespace vpe::normals
