// SPDX-License-Identifier: MIT
// The rules for a bundle's calibration, settings, model and structure, shared by reader and
// writer.
#include "vpe/proto/bundle_contents.h"

#include <cmath>
#include <cstdio>

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/proto/viewing_zone.h"

namespace vpe::proto {

namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    return text;
}

template <std::size_t N>
bool allFinite(const std::array<double, N>& values) {
    for (double v : values) {
        if (!std::isfinite(v)) {
            return false;
        }
    }
    return true;
}

template <std::size_t N>
bool allFinite(const std::array<float, N>& values) {
    for (float v : values) {
        if (!std::isfinite(v)) {
            return false;
        }
    }
    return true;
}

constexpr const char* kChannelNames[3] = {"red", "green", "blue"};

// Calibration files print R with a few digits; 1e-3 (as offline/scene's reader allows)
// accepts those and still refuses scaled or sheared matrices.
constexpr double kRotationTolerance = 1e-3;

std::string checkRotation(const std::array<double, 9>& r, const std::string& what) {
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double dot = 0;
            for (int k = 0; k < 3; ++k) {
                dot += r[3 * i + k] * r[3 * j + k];
            }
            if (std::fabs(dot - (i == j ? 1.0 : 0.0)) > kRotationTolerance) {
                return what + " rotation is not orthonormal (row " + std::to_string(i) + " · row " +
                       std::to_string(j) + " = " + number(dot) + ")";
            }
        }
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (det < 0) {
        return what + " rotation is a reflection (determinant " + number(det) + ")";
    }
    return "";
}

// The projector's rules, for the projector and for the camera (same table, same conventions);
// `what` starts each phrase.
std::string checkPinhole(const ProjectorCalibration& p, const std::string& what) {
    if (p.width == 0 || p.height == 0) {
        return what + " resolution " + std::to_string(p.width) + " x " + std::to_string(p.height) +
               " is empty";
    }
    if (!allFinite(p.intrinsics) || !allFinite(p.distortion) || !allFinite(p.rotation) ||
        !allFinite(p.translation)) {
        return what + " calibration has a value that is not finite";
    }
    const auto& k = p.intrinsics;
    if (!(k[0] > 0 && k[4] > 0)) {
        return what + " intrinsics: focal lengths " + number(k[0]) + ", " + number(k[4]) +
               " are not positive";
    }
    if (k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1) {
        return what + " intrinsics are not a camera matrix (expected [fx s cx; 0 fy cy; 0 0 1])";
    }
    return checkRotation(p.rotation, what);
}

std::string checkCurve(const std::vector<float>& curve, const char* channel) {
    const std::string what = std::string("response curve ") + channel;
    if (curve.size() < 2) {
        return what + " has " + std::to_string(curve.size()) + " samples, needs at least 2";
    }
    for (std::size_t i = 0; i < curve.size(); ++i) {
        if (!std::isfinite(curve[i]) || curve[i] < 0) {
            return what + " sample " + std::to_string(i) + " is " + number(curve[i]) +
                   ", not a finite value ≥ 0";
        }
        if (i > 0 && curve[i] < curve[i - 1]) {
            return what + " is not monotone: sample " + std::to_string(i) + " (" +
                   number(curve[i]) + ") is below sample " + std::to_string(i - 1) + " (" +
                   number(curve[i - 1]) + ")";
        }
    }
    if (!(curve.back() > curve.front())) {
        return what + " is flat";
    }
    return "";
}

}  // namespace

std::string checkProjector(const ProjectorCalibration& projector) {
    return checkPinhole(projector, "projector");
}

std::string checkBundleCamera(const ProjectorCalibration& camera) {
    return checkPinhole(camera, "camera");
}

std::string checkSettings(const RenderSettings& s) {
    if (!allFinite(s.viewerPosition)) {
        return "viewer position is not finite";
    }
    if (s.viewingZone.size() > static_cast<std::size_t>(kMaxViewingZone)) {
        return "viewing zone has " + std::to_string(s.viewingZone.size()) + " eyes, more than " +
               std::to_string(kMaxViewingZone);
    }
    for (const auto& eye : s.viewingZone) {
        if (!allFinite(eye)) {
            return "viewing zone: an eye is not finite";
        }
    }
    for (int c = 0; c < 3; ++c) {
        if (!(s.screenAlbedo[c] > 0 && s.screenAlbedo[c] <= 1)) {
            return std::string("screen albedo ") + kChannelNames[c] + " is " +
                   number(s.screenAlbedo[c]) + ", not in (0, 1]";
        }
        if (!(std::isfinite(s.ambientIrradiance[c]) && s.ambientIrradiance[c] >= 0)) {
            return std::string("ambient radiance ") + kChannelNames[c] + " is " +
                   number(s.ambientIrradiance[c]) + ", not a finite value ≥ 0";
        }
    }
    if (!(std::isfinite(s.peakIrradiance) && s.peakIrradiance > 0)) {
        return "peak irradiance " + number(s.peakIrradiance) + " is not positive";
    }
    if (!(std::isfinite(s.gain) && s.gain > 0)) {
        return "gain " + number(s.gain) + " is not positive";
    }
    for (int c = 0; c < 3; ++c) {
        if (s.response.kind == ResponseKind::kGamma) {
            const float g = s.response.gamma[c];
            if (!(std::isfinite(g) && g > 0)) {
                return std::string("response gamma ") + kChannelNames[c] + " is " + number(g) +
                       ", not positive";
            }
        } else {
            std::string problem = checkCurve(s.response.curve[c], kChannelNames[c]);
            if (!problem.empty()) {
                return problem;
            }
        }
    }
    return "";
}

std::string checkModel(const BundleModel& m) {
    if (m.harmonics < 0 || m.harmonics > kMaxHarmonics) {
        return "model harmonics " + std::to_string(m.harmonics) + " outside 0.." +
               std::to_string(kMaxHarmonics);
    }
    if (!(std::isfinite(m.lambda) && m.lambda >= 0)) {
        return "model lambda " + number(m.lambda) + " is not a finite value ≥ 0";
    }
    if (!m.thetaBasis.empty()) {
        if (std::string problem = checkThetaBasis(m.harmonics, m.thetaBasis); !problem.empty()) {
            return "model.theta_basis: " + problem;
        }
    }
    return "";
}

bool textureSizeFits(std::int64_t width, std::int64_t height) {
    const auto limit = static_cast<std::int64_t>(kMaxBundleTextureSize);
    return width >= 1 && height >= 1 && width <= limit && height <= limit;
}

bool regionCountFits(std::size_t regions) {
    return regions >= 1 && regions <= kMaxBundleRegions;
}

std::string checkRank(const std::string& what, std::int64_t rank, std::int64_t coefficients) {
    if (rank < 1 || rank > coefficients) {
        return what + ": rank " + std::to_string(rank) + " is outside 1.." +
               std::to_string(coefficients);
    }
    return "";
}

std::string checkMeshIndices(std::span<const std::uint32_t> indices, std::uint64_t vertices) {
    for (std::size_t i = 0; i < indices.size(); ++i) {
        if (indices[i] >= vertices) {
            return "mesh indices: triangle " + std::to_string(i / 3) + " refers to vertex " +
                   std::to_string(indices[i]) + ", there are " + std::to_string(vertices);
        }
    }
    return "";
}

bool blendIndexFits(std::int64_t index, std::int64_t projectors) {
    return projectors >= 1 && projectors <= 65535 && index >= 0 && index < projectors;
}

std::string checkBlendShare(float share) {
    return share >= 0 && share <= 1 ? "" : "blend share: a value outside [0, 1]";
}

MixingRule checkMixing(const std::array<double, 9>& m) {
    for (const double v : m) {
        if (!std::isfinite(v) || v < 0) {
            return MixingRule::kNotFiniteOrNegative;
        }
    }
    if (m[0] != 1 || m[4] != 1 || m[8] != 1) {
        return MixingRule::kDiagonalNotOne;
    }
    const double determinant = m[0] * (m[4] * m[8] - m[5] * m[7]) -
                               m[1] * (m[3] * m[8] - m[5] * m[6]) +
                               m[2] * (m[3] * m[7] - m[4] * m[6]);
    return determinant > 1e-6 ? MixingRule::kHolds : MixingRule::kSingular;
}

}  // namespace vpe::proto
