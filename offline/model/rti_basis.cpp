// SPDX-License-Identifier: MIT
// PTM and HSH basis functions.
#include "vpe/model/rti_basis.h"

#include <algorithm>
#include <cmath>

namespace vpe::model {

namespace {

// Hemispherical harmonics of `orders` bands: associated Legendre polynomials P_l^m of
// x = 2 cos θ − 1 (the upper hemisphere mapped onto [−1, 1]) by the standard recurrences,
// scaled to the orthonormal hemispherical norm so that the normal equations stay balanced.
// The sign convention (Condon–Shortley or not) does not matter to a least-squares fit.
void hemisphericalHarmonics(const proto::Vec3d& light, int orders, double* out) {
    constexpr int kMaxOrders = 5;
    const double cosTheta = std::clamp(light.z, -1.0, 1.0);
    const double phi = std::atan2(light.y, light.x);
    const double x = std::clamp(2.0 * cosTheta - 1.0, -1.0, 1.0);
    const double s = std::sqrt(std::max(0.0, 1.0 - x * x));
    double legendre[kMaxOrders][kMaxOrders] = {};
    for (int m = 0; m < orders; ++m) {
        double pmm = 1.0;
        for (int i = 1; i <= m; ++i) {
            pmm *= (2 * i - 1) * s;
        }
        legendre[m][m] = pmm;
        if (m + 1 < orders) {
            legendre[m + 1][m] = x * (2 * m + 1) * pmm;
        }
        for (int l = m + 2; l < orders; ++l) {
            legendre[l][m] =
                ((2 * l - 1) * x * legendre[l - 1][m] - (l + m - 1) * legendre[l - 2][m]) / (l - m);
        }
    }
    int term = 0;
    for (int l = 0; l < orders; ++l) {
        for (int m = -l; m <= l; ++m) {
            const int a = std::abs(m);
            double factorialRatio = 1.0;  // (l − |m|)! / (l + |m|)!
            for (int i = l - a + 1; i <= l + a; ++i) {
                factorialRatio /= i;
            }
            const double norm = std::sqrt((2 * l + 1) / (2.0 * M_PI) * factorialRatio) *
                                (m == 0 ? 1.0 : std::sqrt(2.0));
            const double angular = m > 0 ? std::cos(m * phi) : (m < 0 ? std::sin(a * phi) : 1.0);
            out[term++] = norm * legendre[l][a] * angular;
        }
    }
}

}  // namespace

std::optional<RtiBasis> RtiBasis::parse(std::string_view spec) {
    if (spec.size() < 3 || spec.size() > 5) {
        return std::nullopt;
    }
    const std::string_view family = spec.substr(0, 3);
    const std::string_view count = spec.substr(3);
    if (!std::all_of(count.begin(), count.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
        (!count.empty() && count[0] == '0')) {
        return std::nullopt;
    }
    int terms = count.empty() ? 0 : std::stoi(std::string(count));
    if (family == "ptm") {
        terms = terms == 0 ? 6 : terms;
        if (terms == 6 || terms == 10) {
            return RtiBasis{Kind::kPtm, terms};
        }
    } else if (family == "hsh") {
        terms = terms == 0 ? 16 : terms;
        if (terms == 4 || terms == 9 || terms == 16 || terms == 25) {
            return RtiBasis{Kind::kHsh, terms};
        }
    }
    return std::nullopt;
}

std::string RtiBasis::name() const {
    return (kind == Kind::kPtm ? "ptm" : "hsh") + std::to_string(terms);
}

void RtiBasis::evaluate(const proto::Vec3d& light, double* out) const {
    if (kind == Kind::kHsh) {
        hemisphericalHarmonics(light, static_cast<int>(std::lround(std::sqrt(terms))), out);
        return;
    }
    const double u = light.x, v = light.y;
    out[0] = u * u;
    out[1] = v * v;
    out[2] = u * v;
    out[3] = u;
    out[4] = v;
    out[5] = 1.0;
    if (terms == 10) {
        out[6] = u * u * u;
        out[7] = v * v * v;
        out[8] = u * u * v;
        out[9] = u * v * v;
    }
}

}  // namespace vpe::model
