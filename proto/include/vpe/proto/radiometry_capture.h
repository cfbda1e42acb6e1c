// SPDX-License-Identifier: MIT
// The radiometric capture (proto/RADIOMETRY.md): the flat fields a projector shows so that its
// light on the object can be measured — black, white, each primary at a ladder of levels, and,
// for a camera whose response is not known to be linear, a ramp photographed at bracketed
// exposures — and radiometry.json, the manifest of a folder of them. Written by the device
// (vpe-player --scan, beside the scan) and the simulator (vpe synth-procam), read by
// vpe radiometry: one definition for both sides, as the scan's (SCAN.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/proto/scan_manifest.h"

namespace vpe::proto {

inline constexpr const char* kRadiometryManifestName = "radiometry.json";
inline constexpr const char* kRadiometryFolderName = "radiometry";  // inside a scan folder
inline constexpr int kRadiometryManifestVersion = 1;

enum class FlatFieldKind : std::uint8_t {
    kBlack,    // every channel at level 0: the room's light and the projector's black
    kWhite,    // every channel at level 1
    kPrimary,  // one channel at a level, the others at 0
    kRamp,     // all channels at x / (width − 1): every level at once, for the bracket
};

struct FlatField {
    FlatFieldKind kind = FlatFieldKind::kBlack;
    int channel = 0;       // kPrimary: 0 red, 1 green, 2 blue
    int code = 0;          // kPrimary: the 8-bit level shown
    int exposureStop = 0;  // kRamp: photographed at 2^−stop of the capture's exposure
    // "flat-black", "flat-white", "flat-red-128", "ramp-e2".
    std::string name() const;
    // The camera exposure relative to the capture's: 2^−exposureStop.
    double exposureScale() const;
    // The 8-bit code of each channel at projector pixel column x of `width`.
    std::array<std::uint8_t, 3> codes(int x, int width) const;
};

// How the camera's codes relate to light.
enum class CameraResponseKind : std::uint8_t {
    kLinear,   // raw data: code ∝ light (black level subtracted)
    kUnknown,  // an ISP's output: the capture brackets a ramp to measure it (8-bit only)
};

struct RadiometryParameters {
    int width = 0, height = 0;  // the projector's pixels
    // Levels per primary: codes round(255·k/levels), k = 1..levels. 16 samples a curve finely
    // enough that linear interpolation between them stays within 0.3 % of full output for any
    // gamma-like curve up to γ = 2.6 ((1/16)²/8 × the curve's largest second derivative).
    int levels = 16;
    CameraResponseKind cameraResponse = CameraResponseKind::kLinear;
    int bracketStops = 5;  // kUnknown: ramps at 2^0 … 2^−(stops − 1) of the exposure
};

// The order: black, white, then red, green and blue each from the lowest level up, then (for an
// unknown camera response) the ramp at each stop from 0. Throws StructuredLightError for a size
// outside 8..16384, levels outside 2..64 or stops outside 3..8.
std::vector<FlatField> radiometrySequence(const RadiometryParameters& parameters);

struct RadiometryCamera {
    int width = 0, height = 0;
    int bits = 10;     // 8 or 10
    int channels = 3;  // 3: RGB; the measurement needs colour
    CameraResponseKind response = CameraResponseKind::kLinear;
    double exposureUs = 0;  // of the whole capture (0: unknown); ramps at fractions of it
    double analogueGain = 1;
    std::string source;
};

// As a scan's: a file inside the folder, the flat field's name (FlatField::name()), attempts.
using RadiometryImage = ScanImage;

struct RadiometryManifest {
    RadiometryParameters fields;
    RadiometryCamera camera;
    std::vector<RadiometryImage> images;  // one per flat field, in the sequence's order
    std::string createdBy;
    double projectorLatencyMs = 0;
};

// As scan.json: indented JSON, one image a line.
std::string radiometryManifestJson(const RadiometryManifest& manifest);
// Parses and checks, one ScanManifestError line naming the manifest and the key: format
// "vpe-radiometry", version 1, sizes 1..16384, bits 8 or 10, 3 channels, a camera response
// "linear" or "unknown" (unknown only with 8 bits: the bracket's fit reads 8-bit codes), and
// exactly one image per flat field in order, naming the first missing one.
RadiometryManifest parseRadiometryManifest(std::string_view json, const std::string& source);
RadiometryManifest readRadiometryManifest(const std::filesystem::path& folderOrFile);
void writeRadiometryManifest(const std::filesystem::path& folder,
                             const RadiometryManifest& manifest);

// "NNN-<name>.ppm".
std::string radiometryImageName(std::size_t index, const FlatField& field);

}  // namespace vpe::proto
