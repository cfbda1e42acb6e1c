// SPDX-License-Identifier: MIT
// OscServer end to end on loopback: liblo clients send to an ephemeral port, the test polls the
// server's descriptor as the player's loop does and collects the events; status and ping
// replies reach the sender; a flood is counted and barely logged; a taken port or an absent
// address fails with the documented one-line OscUnavailable.
#include "vpe/firmware/osc/osc_server.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "vpe/firmware/osc/source_allow_list.h"

namespace vpe::firmware {
namespace {

// liblo's LO_TT_IMMEDIATE is a C compound literal, which clang refuses in C++ (-Wpedantic).
constexpr lo_timetag kImmediate{0U, 1U};

OscConfig loopbackConfig(int port = 0) {
    OscConfig config;
    config.address = "127.0.0.1";
    config.port = port;
    return config;
}

// The player's loop, reduced: wait for the descriptor, then let the device drain it.
bool pollOnce(OscServer& server, std::vector<InputEvent>& events, int timeoutMs = 2000) {
    pollfd descriptor{server.pollDescriptors().at(0), POLLIN, 0};
    if (::poll(&descriptor, 1, timeoutMs) <= 0) {
        return false;
    }
    server.onReadable(descriptor.fd, monotonicNowNs(), events);
    return true;
}

std::uint64_t handled(const OscServer& server) {
    return server.dispatcher().counters().accepted + server.dispatcher().counters().rejectedTotal();
}

// Polls until the dispatcher has seen `count` messages in all, or two seconds pass quietly.
void drainUntil(OscServer& server, std::uint64_t count, std::vector<InputEvent>& events) {
    while (handled(server) < count && pollOnce(server, events)) {
    }
}

struct Client {
    lo_address address;
    explicit Client(int port)
        : address(lo_address_new("127.0.0.1", std::to_string(port).c_str())) {}
    ~Client() { lo_address_free(address); }
};

// A client with its own socket, to receive replies (liblo binds it to an unused port).
struct ReplyListener {
    lo_server server = lo_server_new(nullptr, nullptr);
    std::string path;
    std::string types;
    std::vector<OscArgument> arguments;

    ReplyListener() {
        lo_server_add_method(server, nullptr, nullptr, &ReplyListener::handle, this);
    }
    ~ReplyListener() { lo_server_free(server); }

    static int handle(const char* path, const char* types, lo_arg** argv, int argc, lo_message,
                      void* self) {
        auto* listener = static_cast<ReplyListener*>(self);
        listener->path = path;
        listener->types = types;
        // liblo's lo_arg pointers are only 4-byte aligned: copy the values out.
        for (int i = 0; i < argc; ++i) {
            switch (types[i]) {
                case 'i': {
                    std::int32_t value;
                    std::memcpy(&value, argv[i], sizeof value);
                    listener->arguments.emplace_back(value);
                    break;
                }
                case 'f': {
                    float value;
                    std::memcpy(&value, argv[i], sizeof value);
                    listener->arguments.emplace_back(value);
                    break;
                }
                case 's':
                    listener->arguments.emplace_back(
                        std::string(reinterpret_cast<const char*>(argv[i])));
                    break;
                default:
                    listener->arguments.emplace_back(OscOtherArgument{types[i]});
            }
        }
        return 0;
    }

    // Serves `server` until a reply arrives here (or 2 s pass).
    bool awaitReply(OscServer& oscServer) {
        std::vector<InputEvent> events;
        pollOnce(oscServer, events);
        return lo_server_recv_noblock(server, 2000) > 0;
    }
};

TEST(OscServerTest, ListensOnLoopbackOnAnEphemeralPort) {
    OscServer server(loopbackConfig(), OscLimits{}, [](const std::string&) {});
    ASSERT_GT(server.port(), 0);
    EXPECT_EQ(server.url(), "osc.udp://127.0.0.1:" + std::to_string(server.port()));
    EXPECT_EQ(server.description(), "osc (127.0.0.1:" + std::to_string(server.port()) + ")");
    ASSERT_EQ(server.pollDescriptors().size(), 1u);

    // Bound to loopback itself, not the wildcard liblo's own servers use.
    sockaddr_in bound{};
    socklen_t length = sizeof bound;
    ASSERT_EQ(
        ::getsockname(server.pollDescriptors()[0], reinterpret_cast<sockaddr*>(&bound), &length),
        0);
    EXPECT_EQ(bound.sin_family, AF_INET);
    EXPECT_EQ(ntohl(bound.sin_addr.s_addr), INADDR_LOOPBACK);
    EXPECT_EQ(ntohs(bound.sin_port), server.port());
}

TEST(OscServerTest, TurnsMessagesAndBundlesIntoEvents) {
    OscServer server(loopbackConfig(), OscLimits{}, [](const std::string&) {});
    server.dispatcher().setPresetNames({"marble", "brass"});
    Client client(server.port());
    const std::int64_t before = monotonicNowNs();
    ASSERT_GT(lo_send(client.address, "/vpe/light/azimuth", "f", 30.0), 0);
    ASSERT_GT(lo_send(client.address, "/vpe/light/elevation", "i", 15), 0);
    ASSERT_GT(lo_send(client.address, "/vpe/weights/preset", "s", "brass"), 0);

    lo_bundle bundle = lo_bundle_new(kImmediate);
    lo_message distance = lo_message_new();
    lo_message_add_double(distance, 1.5);
    lo_message reset = lo_message_new();
    lo_bundle_add_message(bundle, "/vpe/light/distance", distance);
    lo_bundle_add_message(bundle, "/vpe/light/reset", reset);
    ASSERT_GT(lo_send_bundle(client.address, bundle), 0);
    lo_bundle_free_recursive(bundle);

    std::vector<InputEvent> events;
    drainUntil(server, 5, events);
    ASSERT_EQ(events.size(), 5u);
    for (const InputEvent& event : events) {
        EXPECT_EQ(event.source, InputSource::kOsc);
        EXPECT_GE(event.timestampNs, before);
        EXPECT_LE(event.timestampNs, monotonicNowNs());
    }
    EXPECT_EQ(std::get<AimLight>(events[0].action).azimuthDeg, 30.0);
    EXPECT_EQ(std::get<AimLight>(events[1].action).elevationDeg, 15.0);
    EXPECT_EQ(std::get<SelectPreset>(events[2].action).value, 1);
    EXPECT_EQ(std::get<AimLight>(events[3].action).distanceM, 1.5);
    EXPECT_TRUE(std::holds_alternative<ResetLight>(events[4].action));
    EXPECT_EQ(server.dispatcher().counters().accepted, 5u);
}

TEST(OscServerTest, AnswersStatusToTheSender) {
    OscServer server(loopbackConfig(), OscLimits{}, [](const std::string&) {});
    server.setStatusProvider([] {
        OscStatus status;
        status.framesRendered = 1234;
        status.fps = 59.5;
        status.azimuthDeg = -30;
        status.elevationDeg = 20;
        status.distanceM = 0.8;
        status.preset = "velvet";
        status.activeInput = "knobs";
        return status;
    });
    Client client(server.port());
    lo_send(client.address, "/vpe/light/azimuth", "f", 400.0);  // one rejection to report
    std::vector<InputEvent> events;
    drainUntil(server, 1, events);

    ReplyListener listener;
    ASSERT_GT(lo_send_from(client.address, listener.server, kImmediate, "/vpe/status", ""), 0);
    ASSERT_TRUE(listener.awaitReply(server));
    EXPECT_EQ(listener.path, "/vpe/status/reply");
    EXPECT_EQ(listener.types, "iffffssii");
    const std::vector<OscArgument> expected{
        std::int32_t{1234},   59.5f,           -30.0f, 20.0f, 0.8f, std::string("velvet"),
        std::string("knobs"), std::int32_t{1},  // this query
        std::int32_t{1}};
    EXPECT_EQ(listener.arguments, expected);
    EXPECT_EQ(server.failedReplies(), 0u);
}

TEST(OscServerTest, AnswersPingToANamedPort) {
    OscServer server(loopbackConfig(), OscLimits{}, [](const std::string&) {});
    ReplyListener listener;
    Client client(server.port());
    // Sent from liblo's own client socket; the reply goes to the listener's port instead.
    ASSERT_GT(lo_send(client.address, "/vpe/ping", "i", lo_server_get_port(listener.server)), 0);
    ASSERT_TRUE(listener.awaitReply(server));
    EXPECT_EQ(listener.path, "/vpe/pong");
    EXPECT_EQ(listener.types, "");
}

TEST(OscServerTest, CountsAFloodAndLogsOnlyItsStart) {
    std::vector<std::string> lines;
    OscServer server(loopbackConfig(), OscLimits{},
                     [&](const std::string& line) { lines.push_back(line); });
    Client client(server.port());
    const auto start = std::chrono::steady_clock::now();
    constexpr int kFlood = 10'000;
    constexpr int kBatch = 100;  // well inside the socket's receive buffer
    std::vector<InputEvent> events;
    for (int sent = 0; sent < kFlood; sent += kBatch) {
        for (int i = 0; i < kBatch; ++i) {
            ASSERT_GT(lo_send(client.address, "/vpe/light/azimuth", "f", 1000.0 + i), 0);
        }
        drainUntil(server, static_cast<std::uint64_t>(sent + kBatch), events);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(events.empty());
    EXPECT_EQ(server.dispatcher().counters().rejectedFor(OscRejection::kOutOfRange),
              static_cast<std::uint64_t>(kFlood));
    EXPECT_EQ(server.dispatcher().counters().accepted, 0u);
    // 5 lines at once, then at most one per 10 s of flood.
    EXPECT_GE(lines.size(), 5u);
    EXPECT_LE(lines.size(), 5u + static_cast<std::size_t>(seconds / 10.0) + 1);
    EXPECT_EQ(server.dispatcher().unloggedRejections(), kFlood - lines.size());
    std::printf(
        "[ flood    ] %d datagrams in %.3f s: %llu rejected (out_of_range), %zu lines "
        "logged\n",
        kFlood, seconds,
        static_cast<unsigned long long>(
            server.dispatcher().counters().rejectedFor(OscRejection::kOutOfRange)),
        lines.size());

    // Still listening.
    ASSERT_GT(lo_send(client.address, "/vpe/light/azimuth", "f", 10.0), 0);
    drainUntil(server, kFlood + 1, events);
    ASSERT_EQ(events.size(), 1u);
}

TEST(OscServerTest, CountsDatagramsThatAreNotOsc) {
    std::vector<std::string> lines;
    OscServer server(loopbackConfig(), OscLimits{},
                     [&](const std::string& line) { lines.push_back(line); });
    const int sender = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(sender, 0);
    sockaddr_in target{};
    target.sin_family = AF_INET;
    target.sin_port = htons(static_cast<std::uint16_t>(server.port()));
    target.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const char garbage[] = "GET / HTTP/1.1\r\n";
    ASSERT_GT(::sendto(sender, garbage, sizeof garbage - 1, 0,
                       reinterpret_cast<const sockaddr*>(&target), sizeof target),
              0);
    ASSERT_EQ(
        ::sendto(sender, garbage, 0, 0, reinterpret_cast<const sockaddr*>(&target), sizeof target),
        0);  // an empty datagram
    ::close(sender);
    std::vector<InputEvent> events;
    drainUntil(server, 2, events);
    EXPECT_EQ(server.dispatcher().counters().rejectedFor(OscRejection::kMalformedPacket), 2u);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[1], "osc: empty datagram (malformed_packet)");
    // What the player's report carries per reason (InputDevice::refusals).
    const std::map<std::string, std::uint64_t> refusals = server.refusals();
    EXPECT_EQ(refusals, (std::map<std::string, std::uint64_t>{{"osc.malformed_packet", 2}}));
}

TEST(OscServerTest, ATakenPortIsOneLine) {
    const int holder = ::socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(holder, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::bind(holder, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    socklen_t length = sizeof address;
    ASSERT_EQ(::getsockname(holder, reinterpret_cast<sockaddr*>(&address), &length), 0);
    const int port = ntohs(address.sin_port);

    try {
        OscServer server(loopbackConfig(port), OscLimits{});
        ADD_FAILURE() << "bound a taken port";
    } catch (const OscUnavailable& error) {
        EXPECT_EQ(std::string(error.what()), "osc.udp://127.0.0.1:" + std::to_string(port) +
                                                 ": cannot listen (Address already in use)");
    }
    ::close(holder);
}

TEST(OscServerTest, AnAddressThisMachineLacksIsOneLine) {
    OscConfig config = loopbackConfig(9000);
    config.address = "192.0.2.1";  // TEST-NET-1: assigned to no interface here
    try {
        OscServer server(config, OscLimits{});
        ADD_FAILURE() << "bound 192.0.2.1";
    } catch (const OscUnavailable& error) {
        EXPECT_EQ(std::string(error.what()),
                  "osc.udp://192.0.2.1:9000: cannot listen (Cannot assign requested address)");
    }
    config.address = "localhost";
    try {
        OscServer server(config, OscLimits{});
        ADD_FAILURE() << "resolved a host name";
    } catch (const OscUnavailable& error) {
        EXPECT_EQ(std::string(error.what()).substr(0, 54),
                  "osc.udp://localhost:9000: not a numeric address (Name ");
    }
}

TEST(OscServerTest, ListensOnIpv6Loopback) {
    OscConfig config = loopbackConfig();
    config.address = "::1";
    std::optional<OscServer> server;
    try {
        server.emplace(config, OscLimits{}, [](const std::string&) {});
    } catch (const OscUnavailable& error) {
        GTEST_SKIP() << "no IPv6 loopback here: " << error.what();
    }
    EXPECT_EQ(server->url(), "osc.udp://[::1]:" + std::to_string(server->port()));
    // Debian's liblo is built without IPv6: the datagram is liblo's, the socket is ours.
    lo_message message = lo_message_new();
    lo_message_add_float(message, 45.0f);
    std::size_t size = 0;
    void* datagram = lo_message_serialise(message, "/vpe/light/elevation", nullptr, &size);
    lo_message_free(message);
    const int sender = ::socket(AF_INET6, SOCK_DGRAM, 0);
    ASSERT_GE(sender, 0);
    sockaddr_in6 target{};
    target.sin6_family = AF_INET6;
    target.sin6_port = htons(static_cast<std::uint16_t>(server->port()));
    target.sin6_addr = in6addr_loopback;
    EXPECT_EQ(::sendto(sender, datagram, size, 0, reinterpret_cast<const sockaddr*>(&target),
                       sizeof target),
              static_cast<ssize_t>(size));
    ::close(sender);
    std::free(datagram);
    std::vector<InputEvent> events;
    drainUntil(*server, 1, events);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(std::get<AimLight>(events[0].action).elevationDeg, 45.0);
}

OscConfig allowing(std::vector<std::string> entries, const std::string& address = "127.0.0.1") {
    OscConfig config = loopbackConfig();
    config.address = address;
    std::vector<SourceAllowList::Network> networks;
    for (const std::string& entry : entries) {
        std::string problem;
        networks.push_back(*SourceAllowList::parse(entry, problem));
    }
    config.allow = SourceAllowList(std::move(networks));
    return config;
}

// The gallery LAN's allow list: a sender outside it is counted and logged, never decoded.
TEST(OscServerTest, RefusesSendersOutsideTheAllowList) {
    std::vector<std::string> lines;
    OscServer server(allowing({"192.168.1.0/24", "10.0.0.5"}), OscLimits{},
                     [&](const std::string& line) { lines.push_back(line); });
    EXPECT_EQ(server.description(), "osc (127.0.0.1:" + std::to_string(server.port()) +
                                        ", from 192.168.1.0/24, 10.0.0.5)");
    Client client(server.port());
    ASSERT_GT(lo_send(client.address, "/vpe/light/azimuth", "f", 30.0), 0);
    ASSERT_GT(lo_send(client.address, "/vpe/light/reset", ""), 0);
    std::vector<InputEvent> events;
    drainUntil(server, 2, events);
    EXPECT_TRUE(events.empty());
    EXPECT_EQ(server.dispatcher().counters().accepted, 0u);
    EXPECT_EQ(server.dispatcher().counters().rejectedFor(OscRejection::kSourceNotAllowed), 2u);
    EXPECT_EQ(server.refusals().at("osc.source_not_allowed"), 2u);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(lines[0].substr(0, 34), "osc: datagram of 28 bytes from 127");
    EXPECT_NE(lines[0].find(": not in [osc] allow (source_not_allowed)"), std::string::npos)
        << lines[0];

    // The same sender in a listed network (or listed alone) is read as before.
    for (const char* entry : {"127.0.0.0/8", "127.0.0.1"}) {
        OscServer open(allowing({"10.0.0.5", entry}), OscLimits{}, [](const std::string&) {});
        Client local(open.port());
        ASSERT_GT(lo_send(local.address, "/vpe/light/azimuth", "f", 30.0), 0);
        std::vector<InputEvent> accepted;
        drainUntil(open, 1, accepted);
        EXPECT_EQ(accepted.size(), 1u) << entry;
        EXPECT_EQ(open.dispatcher().counters().rejectedTotal(), 0u) << entry;
    }
}

// A socket bound to "::" sees IPv4 senders as ::ffff:a.b.c.d: they match IPv4 entries.
TEST(OscServerTest, MatchesIpv4SendersOnADualStackSocket) {
    std::optional<OscServer> server;
    try {
        server.emplace(allowing({"127.0.0.1"}, "::"), OscLimits{}, [](const std::string&) {});
    } catch (const OscUnavailable& error) {
        GTEST_SKIP() << "no IPv6 here: " << error.what();
    }
    Client client(server->port());
    ASSERT_GT(lo_send(client.address, "/vpe/light/azimuth", "f", 10.0), 0);
    std::vector<InputEvent> events;
    drainUntil(*server, 1, events);
    EXPECT_EQ(events.size(), 1u);
    EXPECT_EQ(server->dispatcher().counters().rejectedTotal(), 0u);
}

}  // namespace
}  // namespace vpe::firmware
