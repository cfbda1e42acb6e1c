// SPDX-License-Identifier: MIT
// ProjectorRadiometry: how the projector's light reaches the camera, measured per projector
// pixel from the flat fields (proto/RADIOMETRY.md) through the scan's camera↔projector
// correspondence. The model (docs/radiometry.md):
//
//   C_k(p) = D_k(p) + F_k(p) · Σ_c X_kc · g_c(level_c)
//
// C the camera's linear signal in channel k at the surface point projector pixel p lights; D
// the floor — what the camera sees with the projector at level 0 (the room's light, the
// projector's black, the camera's black level); F the irradiance factor — albedo × geometry ×
// the camera's gain, signal per unit of the channel's own primary; X the primaries' crosstalk,
// one 3 × 3 for the whole projector (X_kk = 1); g_c the response above black (0 at 0, 1 at 1).
//
// Why X is global and F per pixel: a matte plaster scales each camera channel by its albedo
// there, the same for every primary, so the per-pixel 3 × 3 is diag(F(p))·X; a per-pixel X
// would be 6 more unknowns per pixel from the same frames, and the measurement says whether it
// is needed: mixingSpread (how much the per-pixel ratios vary over the object) against
// mixingNoise (how much neighbouring pixels differ by noise alone).
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/common/progress_bar.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/radiometry/floor_split.h"
#include "vpe/scan/projector_surface.h"

namespace vpe::radiometry {

struct RadiometryOptions {
    // The white field may saturate on at most this share of the object's pixels.
    double maxSaturatedShare = 0.005;
    // The white field's median above black must reach this share of the camera's range, or the
    // floor (black) is measured in noise.
    double minWhiteSignal = 0.08;
    // The camera's black level per channel (share of its range: the mean of a frame with the
    // lens capped), when known; else fitted, which needs an object of uneven albedo.
    std::optional<std::array<double, 3>> cameraBlack;
    int threads = 0;
};

struct ProjectorRadiometry {
    int width = 0, height = 0;      // the projector's
    std::vector<float> irradiance;  // F: width·height·3, NaN where not measured
    std::vector<float> floor;       // D: width·height·3, NaN where not measured
    std::array<double, 9> mixing{1, 0, 0, 0, 1, 0, 0, 0, 1};  // X, row k camera, column c primary
    std::array<double, 9> mixingSpread{};  // robust σ of the per-pixel X over the object
    std::array<double, 9> mixingNoise{};   // the part of it neighbouring pixels attribute to noise
    // g_c at levels[i] (level 0 first, g = 0 there; the ladder's levels up to 1).
    std::vector<double> levels;
    std::array<std::vector<double>, 3> response;
    // The floor split into the camera's black, the projector's light at level 0 and the room's
    // light, with their errors, or why the object cannot split it (floor_split.h).
    FloorSplit floorSplit;
    std::size_t measured = 0;  // projector pixels with maps
    double whiteSaturatedShare = 0;
    double whiteSignal = 0;  // the white field's median above black, share of the range
    bool cameraLinear = true;
    double exposureUs = 0;
    double fitSeconds = 0;
};

// Fits the model to a radiometric capture (its folder, radiometry.json inside) through a scan's
// surface (surface.exr: points and normals per projector pixel in the camera's frame) and its
// calibration. Throws InputError, one line naming the file and the fix, for a flat field whose
// image is missing or of another size than the camera's, a white field that saturates, a
// capture too dark to measure the floor, or a projector of another size than the scan's.
ProjectorRadiometry measureRadiometry(const std::filesystem::path& capture,
                                      const scan::ProjectorSurface& surface,
                                      const proto::PinholeCamera& camera,
                                      const proto::PinholeCamera& projector,
                                      const RadiometryOptions& options = {},
                                      common::ProgressBar* progress = nullptr);

// The files vpe radiometry writes and vpe bake --radiometry reads.
inline constexpr const char* kIrradianceFile = "irradiance.exr";  // F: R, G, B
inline constexpr const char* kFloorFile = "floor.exr";            // D: R, G, B
inline constexpr const char* kResponseFile = "response.csv";      // level,r,g,b (g above black)
inline constexpr const char* kMeasuredFile = "measured.json";     // X and the rest
inline constexpr const char* kRadiometrySheetFile = "contact-sheet.png";

void writeRadiometry(const ProjectorRadiometry& radiometry, const std::filesystem::path& folder);
// Reads what writeRadiometry wrote: the maps, X, the response. InputError naming the file.
ProjectorRadiometry readRadiometry(const std::filesystem::path& folder);
// The irradiance factor, the floor, the albedo the geometry leaves (F / S), the response curves.
void writeRadiometrySheet(const ProjectorRadiometry& radiometry,
                          const scan::ProjectorSurface& surface,
                          const proto::PinholeCamera& projector, const std::filesystem::path& path);

// S = max(cos θ, 0) / d² of the projector's light on a surface point (camera frame, as the scan
// measures it) with its normal; 0 off the surface.
double projectorGeometry(const proto::PinholeCamera& projector, const float* position,
                         const float* normal);

}  // namespace vpe::radiometry
