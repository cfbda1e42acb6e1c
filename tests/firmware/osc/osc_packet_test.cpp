// SPDX-License-Identifier: MIT
// decodeOscPacket: messages and (nested) bundles as liblo writes them decode to the same
// values; truncated, overrunning, too deeply nested and random datagrams are refused with one
// line, never read out of bounds (the asan build runs this).
#include "vpe/firmware/osc/osc_packet.h"

#include <cstdlib>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <lo/lo.h>

namespace vpe::firmware {
namespace {

// liblo's LO_TT_IMMEDIATE is a C compound literal, which clang refuses in C++ (-Wpedantic).
constexpr lo_timetag kImmediate{0U, 1U};

using Bytes = std::vector<std::uint8_t>;

Bytes serialise(lo_message message, const char* path) {
    std::size_t size = 0;
    void* data = lo_message_serialise(message, path, nullptr, &size);
    Bytes bytes(static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
    std::free(data);
    return bytes;
}

Bytes serialise(lo_bundle bundle) {
    std::size_t size = 0;
    void* data = lo_bundle_serialise(bundle, nullptr, &size);
    Bytes bytes(static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
    std::free(data);
    return bytes;
}

std::vector<OscMessage> messagesOf(const Bytes& bytes) {
    OscPacket packet = decodeOscPacket(bytes);
    if (const auto* problem = std::get_if<std::string>(&packet)) {
        ADD_FAILURE() << *problem;
        return {};
    }
    return std::get<std::vector<OscMessage>>(std::move(packet));
}

std::string problemOf(const Bytes& bytes) {
    const OscPacket packet = decodeOscPacket(bytes);
    const auto* problem = std::get_if<std::string>(&packet);
    return problem != nullptr ? *problem : "(decoded)";
}

// A bundle header: "#bundle\0" and an 8-byte time tag (immediately).
Bytes bundleHeader() {
    Bytes bytes{'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0, 0, 0, 0, 0, 0, 1};
    return bytes;
}

void appendElement(Bytes& bundle, const Bytes& element, std::uint32_t declaredSize) {
    for (int shift = 24; shift >= 0; shift -= 8) {
        bundle.push_back(static_cast<std::uint8_t>(declaredSize >> shift));
    }
    bundle.insert(bundle.end(), element.begin(), element.end());
}

TEST(OscPacketTest, DecodesEveryArgumentType) {
    lo_message message = lo_message_new();
    lo_message_add_int32(message, -7);
    lo_message_add_int64(message, std::int64_t{1} << 40);
    lo_message_add_float(message, 2.5f);
    lo_message_add_double(message, -0.125);
    lo_message_add_string(message, "velvet");
    lo_message_add_symbol(message, "brass");
    lo_message_add_true(message);
    std::uint8_t blob[3] = {1, 2, 3};
    lo_blob b = lo_blob_new(3, blob);
    lo_message_add_blob(message, b);
    const Bytes bytes = serialise(message, "/vpe/test");
    lo_blob_free(b);
    lo_message_free(message);

    const std::vector<OscMessage> messages = messagesOf(bytes);
    ASSERT_EQ(messages.size(), 1u);
    EXPECT_EQ(messages[0].path, "/vpe/test");
    const std::vector<OscArgument> expected{std::int32_t{-7},
                                            std::int64_t{1} << 40,
                                            2.5f,
                                            -0.125,
                                            std::string("velvet"),
                                            std::string("brass"),
                                            OscOtherArgument{'T'},
                                            OscOtherArgument{'b'}};
    EXPECT_EQ(messages[0].arguments, expected);
    EXPECT_EQ(oscTypeTags(messages[0].arguments), "ihfdssTb");
}

TEST(OscPacketTest, DecodesNestedBundlesInOrder) {
    lo_bundle outer = lo_bundle_new(kImmediate);
    lo_bundle inner = lo_bundle_new(kImmediate);
    lo_message first = lo_message_new();
    lo_message_add_float(first, 10.0f);
    lo_message second = lo_message_new();
    lo_message_add_float(second, 20.0f);
    lo_message third = lo_message_new();
    lo_bundle_add_message(outer, "/vpe/light/azimuth", first);
    lo_bundle_add_message(inner, "/vpe/light/elevation", second);
    lo_bundle_add_message(inner, "/vpe/light/reset", third);
    lo_bundle_add_bundle(outer, inner);
    const Bytes bytes = serialise(outer);
    lo_bundle_free_recursive(outer);

    const std::vector<OscMessage> messages = messagesOf(bytes);
    ASSERT_EQ(messages.size(), 3u);
    EXPECT_EQ(messages[0].path, "/vpe/light/azimuth");
    EXPECT_EQ(messages[0].arguments, std::vector<OscArgument>{10.0f});
    EXPECT_EQ(messages[1].path, "/vpe/light/elevation");
    EXPECT_EQ(messages[2].path, "/vpe/light/reset");
    EXPECT_TRUE(messages[2].arguments.empty());

    EXPECT_TRUE(messagesOf(bundleHeader()).empty());  // an empty bundle is valid
}

TEST(OscPacketTest, RefusesMalformedDatagramsWithOneLine) {
    lo_message message = lo_message_new();
    lo_message_add_float(message, 1.0f);
    const Bytes good = serialise(message, "/vpe/light/azimuth");  // 28 bytes
    lo_message_free(message);
    ASSERT_EQ(good.size(), 28u);

    EXPECT_EQ(problemOf({}), "empty datagram");
    EXPECT_EQ(problemOf(Bytes(good.begin(), good.end() - 4)),
              "datagram of 24 bytes: not an OSC message (an argument overruns it)");
    EXPECT_EQ(problemOf(Bytes{'/', 'a', 'b', 'c'}),
              "datagram of 4 bytes: not an OSC message (the address is not a padded string)");

    Bytes overrun = bundleHeader();
    appendElement(overrun, good, 64);
    EXPECT_EQ(problemOf(overrun),
              "datagram of 48 bytes: bundle element of 64 bytes at offset 16 "
              "does not fit the 48-byte bundle");
    Bytes unaligned = bundleHeader();
    appendElement(unaligned, good, 27);
    EXPECT_NE(problemOf(unaligned).find("bundle element of 27 bytes"), std::string::npos);
    Bytes cut = bundleHeader();
    cut.push_back(0);
    EXPECT_EQ(problemOf(cut), "datagram of 17 bytes: bundle ends inside an element size");
    const Bytes header = bundleHeader();
    EXPECT_EQ(problemOf(Bytes(header.begin(), header.begin() + 12)),
              "datagram of 12 bytes: bundle of 12 bytes has no time tag");

    // A good message then a bad one: the bundle is refused whole.
    Bytes mixed = bundleHeader();
    appendElement(mixed, good, 28);
    appendElement(mixed, Bytes(good.begin(), good.end() - 4), 24);
    EXPECT_NE(problemOf(mixed).find("not an OSC message"), std::string::npos);
}

TEST(OscPacketTest, RefusesBundlesNestedTooDeep) {
    lo_message message = lo_message_new();
    const Bytes reset = serialise(message, "/vpe/light/reset");
    lo_message_free(message);
    const auto nest = [&](int depth) {
        Bytes element = reset;
        for (int i = 0; i < depth; ++i) {
            Bytes bundle = bundleHeader();
            appendElement(bundle, element, static_cast<std::uint32_t>(element.size()));
            element = std::move(bundle);
        }
        return element;
    };
    EXPECT_EQ(messagesOf(nest(kMaxOscBundleDepth)).size(), 1u);
    EXPECT_NE(problemOf(nest(kMaxOscBundleDepth + 1)).find("bundles nested deeper than 8"),
              std::string::npos);
}

TEST(OscPacketTest, SurvivesRandomAndMutatedDatagrams) {
    lo_message message = lo_message_new();
    lo_message_add_float(message, 1.0f);
    lo_message_add_string(message, "marble");
    lo_message_add_int64(message, 5);
    const Bytes good = serialise(message, "/vpe/weights/preset");
    lo_message_free(message);
    Bytes bundle = bundleHeader();
    appendElement(bundle, good, static_cast<std::uint32_t>(good.size()));

    std::mt19937 random(7);
    int decoded = 0;
    int refused = 0;
    for (int i = 0; i < 20'000; ++i) {
        Bytes bytes = (i % 2 == 0) ? good : bundle;
        if (i % 3 == 0) {
            bytes.resize(random() % (bytes.size() + 1));
        }
        const int flips = 1 + static_cast<int>(random() % 4);
        for (int k = 0; k < flips && !bytes.empty(); ++k) {
            bytes[random() % bytes.size()] = static_cast<std::uint8_t>(random());
        }
        const OscPacket packet = decodeOscPacket(bytes);
        if (std::holds_alternative<std::string>(packet)) {
            EXPECT_FALSE(std::get<std::string>(packet).empty());
            EXPECT_EQ(std::get<std::string>(packet).find('\n'), std::string::npos);
            ++refused;
        } else {
            ++decoded;
        }
    }
    // Both outcomes occur: the mutations reach past the framing checks into liblo's.
    EXPECT_GT(decoded, 0);
    EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace vpe::firmware
