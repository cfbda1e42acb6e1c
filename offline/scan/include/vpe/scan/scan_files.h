// SPDX-License-Identifier: MIT
// What vpe scan writes and vpe bake --scan reads: the per-projector-pixel surface as one
// OpenEXR (position.X/Y/Z, normal.X/Y/Z, confidence; NaN where unmeasured), the same points as
// a PLY that point-cloud viewers open, and the contact sheet.
#pragma once

#include <filesystem>

#include "vpe/scan/projector_surface.h"

namespace vpe::scan {

inline constexpr const char* kSurfaceFile = "surface.exr";
inline constexpr const char* kPointCloudFile = "points.ply";
inline constexpr const char* kScanSheetFile = "contact-sheet.png";
inline constexpr const char* kDecodedFile = "decoded.exr";
inline constexpr const char* kCalibrationFile = "calibration.yml";  // the one the scan used

void writeSurface(const ProjectorSurface& surface, const std::filesystem::path& path);
// Reads a surface written by writeSurface (InputError naming the file otherwise).
ProjectorSurface readSurface(const std::filesystem::path& path);

// The camera's view of the decoding, for finding what went wrong in a scan: projector.x/y (NaN
// undecoded), status (DecodeStatus as a number), direct, global, white, black, precision.
void writeDecoded(const structured_light::DecodedScan& decoded, const std::filesystem::path& path);

// Binary little-endian PLY: x y z (metres, camera frame), nx ny nz, and the confidence as
// `quality`, one vertex per measured projector pixel (Open3D writes it).
void writePointCloud(const ProjectorSurface& surface, const std::filesystem::path& path);

// The white frame; where decoding stopped and why; the decoded projector x and y; the measured
// depth, normals and confidence in the projector's image.
void writeScanSheet(const structured_light::DecodedScan& decoded, const ProjectorSurface& surface,
                    const std::filesystem::path& path);

}  // namespace vpe::scan
