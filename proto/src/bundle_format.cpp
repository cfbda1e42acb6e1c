// SPDX-License-Identifier: MIT
// The bundle header: encoding, decoding with the checks that need nothing but the header and
// the file's length, and the checksum (zlib's CRC-32).
#include "vpe/proto/bundle_format.h"

#include <algorithm>
#include <cstring>

#include <zlib.h>

#include "printable_text.h"

namespace vpe::proto {

namespace {

template <typename T>
void store(BundleHeaderBytes& bytes, std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof value);
}

template <typename T>
T load(std::span<const std::byte> bytes, std::size_t offset) {
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof value);
    return value;
}

}  // namespace

BundleHeaderBytes encodeBundleHeader(const BundleHeader& header) {
    BundleHeaderBytes bytes{};
    std::memcpy(bytes.data(), kBundleMagic.data(), kBundleMagic.size());
    store(bytes, 4, header.majorVersion);
    store(bytes, 6, header.minorVersion);
    store(bytes, 8, header.flags);
    store(bytes, kBundleChecksumOffset, header.checksum);
    store(bytes, 16, header.metadataOffset);
    store(bytes, 24, header.metadataSize);
    store(bytes, 32, header.fileSize);
    return bytes;
}

BundleHeader decodeBundleHeader(std::span<const std::byte> file, const std::string& name) {
    if (file.empty()) {
        throw BundleError(name, "empty file");
    }
    // The magic first: a file that is not a bundle at all should be called that, whatever
    // its length.
    const std::size_t magicBytes = std::min(file.size(), kBundleMagic.size());
    if (std::memcmp(file.data(), kBundleMagic.data(), magicBytes) != 0) {
        throw BundleError(
            name, "not a vpe bundle: starts with '" +
                      printableText({reinterpret_cast<const char*>(file.data()), magicBytes},
                                    /*asciiOnly=*/true) +
                      "', not 'VPEB'");
    }
    // Then the version, before any other field: another major version may lay them out
    // differently.
    if (file.size() >= 8) {
        const auto major = load<std::uint16_t>(file, 4);
        const auto minor = load<std::uint16_t>(file, 6);
        if (major != kBundleMajorVersion) {
            throw BundleError(name, "format version " + std::to_string(major) + "." +
                                        std::to_string(minor) + ", this reader supports " +
                                        std::to_string(kBundleMajorVersion) + ".x");
        }
    }
    if (file.size() < kBundleHeaderSize) {
        throw BundleError(name, "truncated: " + std::to_string(file.size()) +
                                    " bytes, shorter than the 64-byte header");
    }
    BundleHeader header;
    header.majorVersion = load<std::uint16_t>(file, 4);
    header.minorVersion = load<std::uint16_t>(file, 6);
    header.flags = load<std::uint32_t>(file, 8);
    header.checksum = load<std::uint32_t>(file, kBundleChecksumOffset);
    header.metadataOffset = load<std::uint64_t>(file, 16);
    header.metadataSize = load<std::uint64_t>(file, 24);
    header.fileSize = load<std::uint64_t>(file, 32);
    const std::uint64_t actual = file.size();
    if (header.fileSize > actual) {
        throw BundleError(name, "truncated: header says " + std::to_string(header.fileSize) +
                                    " bytes, file has " + std::to_string(actual));
    }
    if (header.fileSize < actual) {
        throw BundleError(name, "wrong length: header says " + std::to_string(header.fileSize) +
                                    " bytes, file has " + std::to_string(actual));
    }
    return header;
}

std::uint32_t bundleChecksum(std::span<const std::byte> bytes, std::uint32_t previous) {
    // crc32_z takes a size_t length; feed it in bounded pieces anyway, since zlib's
    // z_size_t may be narrower on some builds.
    uLong crc = previous;
    const auto* data = reinterpret_cast<const Bytef*>(bytes.data());
    std::size_t left = bytes.size();
    constexpr std::size_t kPiece = std::size_t{1} << 30;
    while (left > 0) {
        const std::size_t piece = std::min(left, kPiece);
        crc = crc32_z(crc, data, static_cast<z_size_t>(piece));
        data += piece;
        left -= piece;
    }
    return static_cast<std::uint32_t>(crc);
}

}  // namespace vpe::proto
