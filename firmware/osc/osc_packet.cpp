// SPDX-License-Identifier: MIT
// decodeOscPacket: the bundle framing by hand (liblo 0.31 has no public bundle decoder), each
// message by lo_message_deserialise, which checks the address, the type tags and each
// argument against the bytes it was given.
#include "vpe/firmware/osc/osc_packet.h"

#include <cstring>
#include <memory>
#include <string_view>

#include <lo/lo.h>

namespace vpe::firmware {

namespace {

constexpr std::string_view kBundleTag{"#bundle\0", 8};
constexpr std::size_t kBundleHeaderSize = 16;  // the tag, then a 64-bit time tag

std::string libloProblem(int result) {
    switch (result) {
        case LO_ESIZE:
            return "its arguments do not fill it exactly";
        case LO_EINVALIDPATH:
            return "the address is not a padded string";
        case LO_ENOTYPE:
            return "no type tag string";
        case LO_EINVALIDTYPE:
            return "the type tags are not a padded string";
        case LO_EBADTYPE:
            return "an unknown type tag";
        case LO_EINVALIDARG:
            return "an argument overruns it";
        case LO_EALLOC:
            return "out of memory";
        default:
            return "liblo error " + std::to_string(result);
    }
}

struct MessageDeleter {
    void operator()(lo_message message) const { lo_message_free(message); }
};

std::uint32_t bigEndian32(const std::uint8_t* bytes) {
    return static_cast<std::uint32_t>(bytes[0]) << 24 | static_cast<std::uint32_t>(bytes[1]) << 16 |
           static_cast<std::uint32_t>(bytes[2]) << 8 | static_cast<std::uint32_t>(bytes[3]);
}

// lo_arg pointers are only 4-byte aligned inside the message's data: 64-bit values are copied
// out rather than read through the union.
template <class T>
T argumentValue(const lo_arg* argument) {
    T value;
    std::memcpy(&value, argument, sizeof value);
    return value;
}

// One message; an empty string on success, else what is wrong.
std::string decodeMessage(std::span<const std::uint8_t> bytes, std::vector<OscMessage>& out) {
    int result = 0;
    // lo_message_deserialise copies what it reads: the const_cast does not let it write.
    std::unique_ptr<std::remove_pointer_t<lo_message>, MessageDeleter> message(
        lo_message_deserialise(const_cast<std::uint8_t*>(bytes.data()), bytes.size(), &result));
    if (message == nullptr) {
        return std::string("not an OSC message (") + libloProblem(result) + ")";
    }
    OscMessage decoded;
    const char* path = reinterpret_cast<const char*>(bytes.data());
    decoded.path.assign(path, ::strnlen(path, bytes.size()));
    const char* types = lo_message_get_types(message.get());
    const int count = lo_message_get_argc(message.get());
    lo_arg** values = lo_message_get_argv(message.get());
    decoded.arguments.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const lo_arg* value = values[i];
        switch (types[i]) {
            case LO_INT32:
                decoded.arguments.emplace_back(argumentValue<std::int32_t>(value));
                break;
            case LO_INT64:
                decoded.arguments.emplace_back(argumentValue<std::int64_t>(value));
                break;
            case LO_FLOAT:
                decoded.arguments.emplace_back(argumentValue<float>(value));
                break;
            case LO_DOUBLE:
                decoded.arguments.emplace_back(argumentValue<double>(value));
                break;
            case LO_STRING:
            case LO_SYMBOL:
                decoded.arguments.emplace_back(std::string(reinterpret_cast<const char*>(value)));
                break;
            default:
                decoded.arguments.emplace_back(OscOtherArgument{types[i]});
                break;
        }
    }
    out.push_back(std::move(decoded));
    return {};
}

bool isBundle(std::span<const std::uint8_t> bytes) {
    return bytes.size() >= kBundleTag.size() &&
           std::memcmp(bytes.data(), kBundleTag.data(), kBundleTag.size()) == 0;
}

std::string decodeElement(std::span<const std::uint8_t> bytes, int depth,
                          std::vector<OscMessage>& out) {
    if (!isBundle(bytes)) {
        return decodeMessage(bytes, out);
    }
    if (depth >= kMaxOscBundleDepth) {
        return "bundles nested deeper than " + std::to_string(kMaxOscBundleDepth);
    }
    if (bytes.size() < kBundleHeaderSize) {
        return "bundle of " + std::to_string(bytes.size()) + " bytes has no time tag";
    }
    std::size_t offset = kBundleHeaderSize;
    while (offset < bytes.size()) {
        if (bytes.size() - offset < 4) {
            return "bundle ends inside an element size";
        }
        const std::uint32_t size = bigEndian32(bytes.data() + offset);
        offset += 4;
        if (size == 0 || size % 4 != 0 || size > bytes.size() - offset) {
            return "bundle element of " + std::to_string(size) + " bytes at offset " +
                   std::to_string(offset - 4) + " does not fit the " +
                   std::to_string(bytes.size()) + "-byte bundle";
        }
        if (std::string problem = decodeElement(bytes.subspan(offset, size), depth + 1, out);
            !problem.empty()) {
            return problem;
        }
        offset += size;
    }
    return {};
}

}  // namespace

OscPacket decodeOscPacket(std::span<const std::uint8_t> datagram) {
    std::vector<OscMessage> messages;
    if (datagram.empty()) {
        return std::string("empty datagram");
    }
    if (std::string problem = decodeElement(datagram, 0, messages); !problem.empty()) {
        return "datagram of " + std::to_string(datagram.size()) + " bytes: " + problem;
    }
    return messages;
}

}  // namespace vpe::firmware
