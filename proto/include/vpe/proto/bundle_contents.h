// SPDX-License-Identifier: MIT
// The small, by-value parts of a bundle — projector calibration, render settings, model —
// and the rules a bundle must satisfy. The reader decodes the metadata into these; the offline
// writer takes them as input; both refuse values for the same reasons (the rules below, one
// definition for both sides).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace vpe::proto {

// As OpenCV's stereo calibration writes it: x_proj = R·x + T maps a point x of the object
// frame (metres) into the projector's camera frame; K projects it onto the projector's pixels.
struct ProjectorCalibration {
    std::uint32_t width = 0;  // pixels
    std::uint32_t height = 0;
    std::array<double, 9> intrinsics{};   // K, row-major; bottom row (0, 0, 1)
    std::array<double, 5> distortion{};   // k1, k2, p1, p2, k3
    std::array<double, 9> rotation{};     // R, row-major, a rotation
    std::array<double, 3> translation{};  // T, metres
};

enum class ResponseKind { kGamma, kCurve };

// The projector's relative output r(v) for an input level v ∈ [0, 1], per channel (R, G, B),
// as the bundle stores it: v^gamma, or a sampled curve (sample i at v = i / (N − 1), linear in
// between). The data; its math — evaluation and inverse — is ResponseFunction
// (response_function.h, responseFunctionOf).
struct ResponseCurves {
    ResponseKind kind = ResponseKind::kGamma;
    std::array<float, 3> gamma{2.2f, 2.2f, 2.2f};  // kGamma
    std::array<std::vector<float>, 3> curve;       // kCurve: N ≥ 2, non-decreasing, rising
};

struct RenderSettings {
    std::array<float, 3> viewerPosition{};                   // object frame, metres
    std::array<float, 3> screenAlbedo{0.85f, 0.85f, 0.85f};  // white plaster
    std::array<float, 3> ambientIrradiance{};  // room light on the screen, unit of peakIrradiance
    ResponseCurves response;
    // Irradiance the projector gives at relative output r = 1, 1 m away, at normal incidence
    // (it falls off as cos θ / d², renderer/README.md).
    float peakIrradiance = 1.0f;
    float gain = 1.0f;  // global exposure of the rendered radiance
    // Format 1.6: the visitors' eyes the view-dependent light is drawn for (proto/viewing_zone.h),
    // object frame, metres, at most kMaxViewingZone; empty: viewerPosition alone.
    std::vector<std::array<float, 3>> viewingZone;
};

// The Fourier BRDF model the textures hold (proto/MODEL.md).
struct BundleModel {
    int harmonics = 0;  // M
    double lambda = 0;  // λ of the fit (informative)
    // The θs basis the bake chose (format 1.1, proto/theta_basis.h): K × (2M + 1) values,
    // function j at [j·n, (j + 1)·n), orthonormal over θs ∈ [0, π]; the device renders each
    // texel's θs part projected onto it. Empty: none, rendered exactly (ThetaBasis::full).
    std::vector<float> thetaBasis;
    // K, the number of θs functions (0 when there is no basis).
    int thetaBasisSize() const { return static_cast<int>(thetaBasis.size()) / (2 * harmonics + 1); }
    // Values per texel: 2M + 2 per colour channel, three channels.
    int coefficientsPerTexel() const { return 3 * (2 * harmonics + 2); }
};

// Why these values cannot be rendered, as a phrase naming the field; "" when they can.
std::string checkProjector(const ProjectorCalibration& projector);
// The installation's camera (format 1.3, Bundle.camera) has the projector's type and rules;
// its phrases name "camera" instead.
std::string checkBundleCamera(const ProjectorCalibration& camera);
std::string checkSettings(const RenderSettings& settings);
std::string checkModel(const BundleModel& model);

// The bundle's structural rules. Where the writer and the reader word a refusal alike, the
// check returns it ("" when the rule holds); where each words it its own way (what it was given,
// or what the file holds), the rule says which way it fails and each side keeps its words.

// Textures of 1..kMaxBundleTextureSize a side (what GLES 3.1 guarantees on the Pi).
bool textureSizeFits(std::int64_t width, std::int64_t height);
// 1..kMaxBundleRegions regions.
bool regionCountFits(std::size_t regions);
// A low-rank map's rank, 1..the values per texel: "WHAT: rank R is outside 1..C".
std::string checkRank(const std::string& what, std::int64_t rank, std::int64_t coefficients);
// Every index names a vertex: an index past them would have the GPU read out of bounds.
std::string checkMeshIndices(std::span<const std::uint32_t> indices, std::uint64_t vertices);
// Projector `index` of `projectors` (1..65535 of them).
bool blendIndexFits(std::int64_t index, std::int64_t projectors);
// A projector's share of the light at one of its pixels, in [0, 1].
std::string checkBlendShare(float share);
// The radiometry's crosstalk X: finite values ≥ 0, its diagonal 1, invertible (the device
// inverts it).
enum class MixingRule { kHolds, kNotFiniteOrNegative, kDiagonalNotOne, kSingular };
MixingRule checkMixing(const std::array<double, 9>& mixing);

}  // namespace vpe::proto
