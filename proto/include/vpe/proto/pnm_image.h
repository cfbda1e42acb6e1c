// SPDX-License-Identifier: MIT
// Binary PGM and PPM (P5, P6) files, written atomically: how the device stores what its camera
// captured for a scan (proto/SCAN.md). The device has no image library and these need none;
// the offline tools read them with OpenImageIO, which scales samples by the file's maxval.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace vpe::proto {

// samples: width·height·channels values in [0, maxValue], rows from the top, channels
// interleaved; channels 1 (PGM) or 3 (PPM); maxValue 1..65535 (one byte per sample up to 255,
// two big-endian bytes above: 1023 for a 10-bit camera). Written to a temporary file beside
// `path` and renamed over it, so a reader never sees half an image. Throws
// std::invalid_argument for inconsistent sizes or a sample above maxValue, std::runtime_error
// "PATH: cannot write (reason)" when the file cannot be written.
void writePnmAtomically(const std::filesystem::path& path, int width, int height, int channels,
                        int maxValue, std::span<const std::uint16_t> samples);

// The same from 8-bit samples (maxValue 255).
void writePnmAtomically(const std::filesystem::path& path, int width, int height, int channels,
                        std::span<const std::uint8_t> samples);

}  // namespace vpe::proto
