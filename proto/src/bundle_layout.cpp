// SPDX-License-Identifier: MIT
// The bundle file's layout: payload placement, the settling metadata, assembly in memory.
#include "vpe/proto/bundle_layout.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace vpe::proto {

std::uint64_t payloadElementBytes(fb::ElementType type) {
    return type == fb::ElementType::UInt8 ? 1 : type == fb::ElementType::Float16 ? 2 : 4;
}

std::uint64_t alignPayloadOffset(std::uint64_t offset) {
    return (offset + kBundlePayloadAlignment - 1) / kBundlePayloadAlignment *
           kBundlePayloadAlignment;
}

std::size_t BundleLayout::add(fb::ElementType type, std::vector<std::uint32_t> shape) {
    PayloadPlacement payload;
    payload.type = type;
    payload.size = payloadElementBytes(type);
    for (const std::uint32_t dimension : shape) {
        payload.size *= dimension;
    }
    payload.shape = std::move(shape);
    payloads_.push_back(std::move(payload));
    return payloads_.size() - 1;
}

std::vector<std::uint8_t> BundleLayout::settle(
    const std::function<std::vector<std::uint8_t>(const std::vector<PayloadPlacement>&)>&
        buildMetadata) {
    std::vector<std::uint8_t> metadata;
    for (std::uint64_t size = 0, pass = 0;; size = metadata.size(), ++pass) {
        std::uint64_t offset = alignPayloadOffset(kBundleHeaderSize + size);
        fileSize_ = kBundleHeaderSize + size;
        for (PayloadPlacement& payload : payloads_) {
            payload.offset = offset;
            fileSize_ = offset + payload.size;
            offset = alignPayloadOffset(fileSize_);
        }
        metadata = buildMetadata(payloads_);
        if (metadata.size() == size) {
            metadataSize_ = size;
            return metadata;
        }
        if (pass > 4) {
            throw std::logic_error("bundle layout: the metadata's size does not settle");
        }
    }
}

BundleHeader BundleLayout::header(std::uint16_t minorVersion) const {
    BundleHeader header;
    header.minorVersion = minorVersion;
    header.metadataOffset = kBundleHeaderSize;
    header.metadataSize = metadataSize_;
    header.fileSize = fileSize_;
    return header;
}

flatbuffers::Offset<fb::Payload> payloadReference(flatbuffers::FlatBufferBuilder& builder,
                                                  const PayloadPlacement& payload) {
    return fb::CreatePayloadDirect(builder, payload.offset, payload.size, payload.type,
                                   &payload.shape);
}

std::vector<std::byte> assembleBundle(const BundleLayout& layout,
                                      const std::vector<std::uint8_t>& metadata,
                                      const std::vector<std::span<const std::byte>>& payloadBytes,
                                      std::uint16_t minorVersion) {
    const BundleHeader header = layout.header(minorVersion);
    const std::vector<PayloadPlacement>& payloads = layout.payloads();
    if (metadata.size() != header.metadataSize || payloadBytes.size() != payloads.size()) {
        throw std::logic_error("bundle layout: assembly does not match the settled layout");
    }
    std::vector<std::byte> bytes(header.fileSize);
    std::memcpy(bytes.data() + header.metadataOffset, metadata.data(), metadata.size());
    for (std::size_t i = 0; i < payloads.size(); ++i) {
        if (payloadBytes[i].size() != payloads[i].size) {
            throw std::logic_error("bundle layout: payload " + std::to_string(i) +
                                   " differs from its placement's size");
        }
        std::memcpy(bytes.data() + payloads[i].offset, payloadBytes[i].data(),
                    payloadBytes[i].size());
    }
    const BundleHeaderBytes encoded = encodeBundleHeader(header);
    std::memcpy(bytes.data(), encoded.data(), encoded.size());
    sealBundleChecksum(bytes);
    return bytes;
}

void sealBundleChecksum(std::span<std::byte> bytes) {
    const std::uint32_t crc = bundleChecksum(bytes.subspan(kBundleHeaderSize));
    std::memcpy(bytes.data() + kBundleChecksumOffset, &crc, sizeof crc);
}

}  // namespace vpe::proto
