// SPDX-License-Identifier: MIT
// The device bundle's on-disk frame (proto/BUNDLE.md): the fixed 64-byte header, the format
// version, the limits, the checksum, and the error readers throw. Shared by the device reader
// and the offline writer so that the layout is written down once.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "vpe/proto/input_error.h"

namespace vpe::proto {

// Payloads are read in place as little-endian arrays (the Raspberry Pi and x86-64 both are).
static_assert(std::endian::native == std::endian::little, "bundles are little-endian");

inline constexpr std::array<char, 4> kBundleMagic{'V', 'P', 'E', 'B'};
// Readers accept any minor version of their major one (minor versions only append fields).
inline constexpr std::uint16_t kBundleMajorVersion = 1;
// 1.1 appended Model.theta_basis; 1.2 Textures.wrap_u and CoefficientMap.detail_normals; 1.3
// Bundle.camera; 1.4 Bundle.radiometry; 1.5 Bundle.blend; 1.6 RenderSettings.viewing_zone.
inline constexpr std::uint16_t kBundleMinorVersion = 6;

inline constexpr std::size_t kBundleHeaderSize = 64;
// Where the header keeps the checksum (a little-endian uint32, like every header field).
inline constexpr std::size_t kBundleChecksumOffset = 12;
// Payloads start on 64-byte boundaries: a cache line, and more than any GL upload needs.
inline constexpr std::uint64_t kBundlePayloadAlignment = 64;
// GLES 3.1's guaranteed MAX_TEXTURE_SIZE on the Raspberry Pi 4 and 5 (VideoCore VI / VII).
inline constexpr std::uint32_t kMaxBundleTextureSize = 4096;
// GLES 3.1's guaranteed minimum MAX_ARRAY_TEXTURE_LAYERS: the α layers of a preset are one
// texture array, one layer per region.
inline constexpr std::uint32_t kMaxBundleRegions = 256;
// The per-texel coefficient order inside a bundle (BUNDLE.md): value 3·k + c holds
// coefficient k (fourier_brdf.h order: kd, a0, a1, b1, ...) of colour channel c (R, G, B).
inline constexpr const char* kBundleCoefficientLayout = "fourier_brdf:k_major_rgb";

constexpr int bundleCoefficientIndex(int coefficient, int channel) {
    return 3 * coefficient + channel;
}

// Every problem with a bundle: what() is one line, "<file>: <problem>"; problem() is the
// message without the file name.
class BundleError : public InputError {
public:
    BundleError(const std::string& file, const std::string& problem)
        : InputError(std::filesystem::path(file), problem) {}
};

// The header, decoded. On disk (little-endian):
//   0 magic "VPEB" | 4 u16 major | 6 u16 minor | 8 u32 flags | 12 u32 checksum |
//   16 u64 metadata offset | 24 u64 metadata size | 32 u64 file size | 40..63 reserved, zero
struct BundleHeader {
    std::uint16_t majorVersion = kBundleMajorVersion;
    std::uint16_t minorVersion = kBundleMinorVersion;
    std::uint32_t flags = 0;     // none defined in 1.x; readers ignore unknown bits
    std::uint32_t checksum = 0;  // zlib's CRC-32 of bytes [64, file size)
    std::uint64_t metadataOffset = 0;
    std::uint64_t metadataSize = 0;
    std::uint64_t fileSize = 0;
};

using BundleHeaderBytes = std::array<std::byte, kBundleHeaderSize>;

BundleHeaderBytes encodeBundleHeader(const BundleHeader& header);

// Decodes the header of a whole file's bytes. Checks, in this order, what can be checked
// without the rest of the file: not empty, the magic, the major version, the header's length,
// the file's length against the header's. Throws BundleError naming `file`.
BundleHeader decodeBundleHeader(std::span<const std::byte> file, const std::string& name);

// CRC-32 (zlib's), continued from `previous` so that writers can compute it as they stream.
std::uint32_t bundleChecksum(std::span<const std::byte> bytes, std::uint32_t previous = 0);

}  // namespace vpe::proto
