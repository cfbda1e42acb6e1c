// SPDX-License-Identifier: MIT
// Where everything goes in a bundle file (BUNDLE.md): the header, the metadata right after it,
// then each payload at the next multiple of kBundlePayloadAlignment, in the order added. The
// one definition the bake's writer and the test bundles share. The metadata holds the
// payloads' offsets, which start after the metadata, so a writer builds the metadata until its
// size stops changing (settle).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/bundle_generated.h"

namespace vpe::proto {

// Bytes per element of a payload type.
std::uint64_t payloadElementBytes(fb::ElementType type);

// The next offset a payload may start at.
std::uint64_t alignPayloadOffset(std::uint64_t offset);

// One payload as the metadata references it.
struct PayloadPlacement {
    fb::ElementType type = fb::ElementType::Float32;
    std::vector<std::uint32_t> shape;
    std::uint64_t size = 0;    // element bytes × the shape's product
    std::uint64_t offset = 0;  // from the file's start, once settled
};

class BundleLayout {
public:
    // Adds a payload after the ones added before; returns its index.
    std::size_t add(fb::ElementType type, std::vector<std::uint32_t> shape);

    // Calls buildMetadata with the payloads placed after a metadata of the previous build's
    // size until that size is stable, and returns the last build. Throws std::logic_error if
    // it does not settle (offsets change values in the metadata, never its shape, so the
    // second pass settles).
    std::vector<std::uint8_t> settle(
        const std::function<std::vector<std::uint8_t>(const std::vector<PayloadPlacement>&)>&
            buildMetadata);

    const std::vector<PayloadPlacement>& payloads() const { return payloads_; }
    // The header of the settled layout (checksum left 0: it covers bytes yet to be written).
    BundleHeader header(std::uint16_t minorVersion = kBundleMinorVersion) const;

private:
    std::vector<PayloadPlacement> payloads_;
    std::uint64_t metadataSize_ = 0;
    std::uint64_t fileSize_ = 0;
};

// A reference to a placed payload, for building the metadata.
flatbuffers::Offset<fb::Payload> payloadReference(flatbuffers::FlatBufferBuilder& builder,
                                                  const PayloadPlacement& payload);

// The whole file in memory from a settled layout, its metadata and each payload's bytes (in
// the order added; each exactly its placement's size), the checksum sealed.
std::vector<std::byte> assembleBundle(const BundleLayout& layout,
                                      const std::vector<std::uint8_t>& metadata,
                                      const std::vector<std::span<const std::byte>>& payloadBytes,
                                      std::uint16_t minorVersion = kBundleMinorVersion);

// Recomputes the checksum of a whole file's bytes in place (after a test changed them).
void sealBundleChecksum(std::span<std::byte> bytes);

}  // namespace vpe::proto
