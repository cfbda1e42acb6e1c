// SPDX-License-Identifier: MIT
// OscServer: a non-blocking UDP socket bound with getaddrinfo to a numeric address, drained
// with recvfrom; liblo decodes (decodeOscPacket) and encodes the replies (lo_message_serialise).
#include "vpe/firmware/osc/osc_server.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>

#include <lo/lo.h>
#include <netdb.h>
#include <netinet/in.h>
#include <unistd.h>

#include "vpe/firmware/osc/osc_packet.h"

namespace vpe::firmware {

namespace {

// The largest UDP payload (IPv4: 65535 − 8 − 20); a longer datagram cannot arrive.
constexpr std::size_t kMaxDatagram = 65507;

std::string hostForUrl(const std::string& address) {
    return address.find(':') == std::string::npos ? address : "[" + address + "]";
}

std::int32_t saturatedInt32(std::uint64_t value) {
    return static_cast<std::int32_t>(
        std::min<std::uint64_t>(value, std::numeric_limits<std::int32_t>::max()));
}

std::int32_t saturatedInt32(std::int64_t value) {
    return static_cast<std::int32_t>(std::clamp<std::int64_t>(
        value, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()));
}

struct MessageDeleter {
    void operator()(lo_message message) const { lo_message_free(message); }
};
using MessagePointer = std::unique_ptr<std::remove_pointer_t<lo_message>, MessageDeleter>;

}  // namespace

OscServer::OscServer(const OscConfig& config, const OscLimits& limits, RateLimitedLog::Sink log)
    : dispatcher_(limits, std::move(log)), host_(hostForUrl(config.address)), allow_(config.allow) {
    const auto unavailable = [&](const std::string& problem) {
        return OscUnavailable("osc.udp://" + host_ + ":" + std::to_string(config.port) + ": " +
                              problem);
    };
    if (config.port < 0 || config.port > 65535) {
        throw unavailable("port outside 0..65535");
    }
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    hints.ai_flags = AI_NUMERICHOST | AI_NUMERICSERV | AI_PASSIVE;
    addrinfo* found = nullptr;
    const std::string service = std::to_string(config.port);
    if (const int error = ::getaddrinfo(config.address.c_str(), service.c_str(), &hints, &found);
        error != 0) {
        throw unavailable(std::string("not a numeric address (") + ::gai_strerror(error) + ")");
    }
    const std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> addresses(found, ::freeaddrinfo);

    fd_ = ::socket(found->ai_family, found->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC,
                   found->ai_protocol);
    if (fd_ < 0) {
        throw unavailable(std::string("cannot open a socket (") + std::strerror(errno) + ")");
    }
    if (::bind(fd_, found->ai_addr, found->ai_addrlen) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        throw unavailable(std::string("cannot listen (") + std::strerror(error) + ")");
    }
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &length) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        throw unavailable(std::string("cannot read the bound port (") + std::strerror(error) + ")");
    }
    port_ = bound.ss_family == AF_INET6
                ? ntohs(reinterpret_cast<const sockaddr_in6*>(&bound)->sin6_port)
                : ntohs(reinterpret_cast<const sockaddr_in*>(&bound)->sin_port);
    url_ = "osc.udp://" + host_ + ":" + std::to_string(port_);
    buffer_.assign(kMaxDatagram, 0);
}

OscServer::~OscServer() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

std::string OscServer::description() const {
    return "osc (" + host_ + ":" + std::to_string(port_) +
           (allow_.allowsEverySender() ? "" : ", from " + allow_.describe()) + ")";
}

void OscServer::setStatusProvider(std::function<OscStatus()> provider) {
    statusProvider_ = std::move(provider);
}

void OscServer::onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) {
    if (fd != fd_) {
        return;
    }
    for (int i = 0; i < kMaxDatagramsPerWake; ++i) {
        sockaddr_storage sender{};
        socklen_t senderLength = sizeof sender;
        const ssize_t received =
            ::recvfrom(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT | MSG_TRUNC,
                       reinterpret_cast<sockaddr*>(&sender), &senderLength);
        if (received < 0) {
            if (errno == EINTR) {
                continue;
            }
            // EAGAIN: drained. Anything else (a pending ICMP error on some kernels) is not
            // about a datagram: stop for this turn, the loop polls again.
            return;
        }
        handleDatagram(static_cast<std::size_t>(received), sender, senderLength, nowNs, events);
    }
}

void OscServer::handleDatagram(std::size_t size, const sockaddr_storage& sender,
                               socklen_t senderLength, std::int64_t nowNs,
                               std::vector<InputEvent>& events) {
    if (!allow_.allows(sender)) {
        dispatcher_.rejectSource("datagram of " + std::to_string(size) + " bytes from " +
                                     describeSender(sender) + ": not in [osc] allow",
                                 nowNs);
        return;
    }
    if (size > buffer_.size()) {  // MSG_TRUNC reports the datagram's real size
        dispatcher_.rejectMalformed(
            "datagram of " + std::to_string(size) + " bytes: longer than any UDP payload", nowNs);
        return;
    }
    OscPacket packet = decodeOscPacket(std::span(buffer_.data(), size));
    if (const auto* problem = std::get_if<std::string>(&packet)) {
        dispatcher_.rejectMalformed(*problem, nowNs);
        return;
    }
    for (const OscMessage& message : std::get<std::vector<OscMessage>>(packet)) {
        OscOutcome outcome = dispatcher_.dispatch(message.path, message.arguments, nowNs);
        if (outcome.event) {
            events.push_back(std::move(*outcome.event));
        }
        if (outcome.reply) {
            reply(*outcome.reply, sender, senderLength);
        }
    }
}

void OscServer::reply(const OscReplyRequest& request, const sockaddr_storage& sender,
                      socklen_t senderLength) {
    MessagePointer message(lo_message_new());
    if (message == nullptr) {
        ++failedReplies_;
        return;
    }
    const char* path = "/vpe/pong";
    if (request.query == OscQuery::kStatus) {
        path = "/vpe/status/reply";
        const OscStatus status = statusProvider_ ? statusProvider_() : OscStatus{};
        const OscCounters& counters = dispatcher_.counters();
        lo_message_add_int32(message.get(), saturatedInt32(status.framesRendered));
        lo_message_add_float(message.get(), static_cast<float>(status.fps));
        lo_message_add_float(message.get(), static_cast<float>(status.azimuthDeg));
        lo_message_add_float(message.get(), static_cast<float>(status.elevationDeg));
        lo_message_add_float(message.get(), static_cast<float>(status.distanceM));
        lo_message_add_string(message.get(), status.preset.c_str());
        lo_message_add_string(message.get(), status.activeInput.c_str());
        lo_message_add_int32(message.get(), saturatedInt32(counters.accepted));
        lo_message_add_int32(message.get(), saturatedInt32(counters.rejectedTotal()));
    }
    sockaddr_storage target = sender;
    if (request.port) {
        const auto port = htons(static_cast<std::uint16_t>(*request.port));
        if (target.ss_family == AF_INET6) {
            reinterpret_cast<sockaddr_in6*>(&target)->sin6_port = port;
        } else {
            reinterpret_cast<sockaddr_in*>(&target)->sin_port = port;
        }
    }
    std::size_t size = 0;
    void* bytes = lo_message_serialise(message.get(), path, nullptr, &size);
    if (bytes == nullptr) {
        ++failedReplies_;
        return;
    }
    const ssize_t sent = ::sendto(fd_, bytes, size, MSG_DONTWAIT | MSG_NOSIGNAL,
                                  reinterpret_cast<const sockaddr*>(&target), senderLength);
    std::free(bytes);
    if (sent != static_cast<ssize_t>(size)) {
        ++failedReplies_;
    }
}

}  // namespace vpe::firmware
