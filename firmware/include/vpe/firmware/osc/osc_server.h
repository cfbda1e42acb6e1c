// SPDX-License-Identifier: MIT
// OscServer: the OSC input. A UDP socket bound to the board's address and port; each datagram
// from a sender the [osc] allow list admits is decoded with liblo (decodeOscPacket), handed to
// its OscDispatcher, and /vpe/status and /vpe/ping are answered from the same socket to the
// sender. A datagram from any other sender is counted (source_not_allowed) and dropped unread.
//
// Why not lo_server: liblo 0.31 binds every UDP server to the wildcard address (its
// getaddrinfo has a NULL host; lo_server_new_from_url takes the URL's host for a multicast
// group and fails with IP_ADD_MEMBERSHIP on 127.0.0.1), reports port 0 for an ephemeral port
// and turns "Address already in use" into "cannot find free port". The player must listen on
// loopback only unless the board says otherwise, so it owns the socket and uses liblo for the
// OSC wire format.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/socket.h>

#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/osc/osc_config.h"
#include "vpe/firmware/osc/osc_dispatcher.h"

namespace vpe::firmware {

// The socket cannot be opened: "osc.udp://127.0.0.1:9000: cannot listen (Address already in
// use)". The player logs it and runs without OSC.
class OscUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The player's state for /vpe/status/reply (proto/OSC.md lists the reply's arguments).
struct OscStatus {
    std::int64_t framesRendered = 0;
    double fps = 0;
    double azimuthDeg = 0, elevationDeg = 0, distanceM = 0;
    std::string preset;       // the preset's name
    std::string activeInput;  // inputSourceName of the source steering the light
};

class OscServer : public InputDevice {
public:
    // Datagrams read per onReadable: the rest of a flood waits for the next loop turn (the
    // descriptor stays readable), so OSC cannot starve the frame loop.
    static constexpr int kMaxDatagramsPerWake = 256;

    // Binds config.address:config.port (config.enabled is the caller's to check). Throws
    // OscUnavailable.
    OscServer(const OscConfig& config, const OscLimits& limits, RateLimitedLog::Sink log = {});
    ~OscServer() override;

    // "osc (127.0.0.1:9000)", "osc (0.0.0.0:9000, from 192.168.1.0/24, 10.0.0.5)"
    std::string description() const override;
    std::vector<int> pollDescriptors() const override { return {fd_}; }
    void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) override;
    std::map<std::string, std::uint64_t> refusals() const override {
        return dispatcher_.counters().rejectionsByName();
    }

    // The bound port (the ephemeral one when the config asked for 0).
    int port() const { return port_; }
    // "osc.udp://127.0.0.1:9000"
    const std::string& url() const { return url_; }

    // Called for each /vpe/status; without one, the reply carries zeros and empty names.
    void setStatusProvider(std::function<OscStatus()> provider);

    OscDispatcher& dispatcher() { return dispatcher_; }
    const OscDispatcher& dispatcher() const { return dispatcher_; }
    // Replies the socket would not take (the sender's buffer full, unreachable, …).
    std::uint64_t failedReplies() const { return failedReplies_; }

private:
    void handleDatagram(std::size_t size, const sockaddr_storage& sender, socklen_t senderLength,
                        std::int64_t nowNs, std::vector<InputEvent>& events);
    void reply(const OscReplyRequest& request, const sockaddr_storage& sender,
               socklen_t senderLength);

    OscDispatcher dispatcher_;
    std::function<OscStatus()> statusProvider_;
    int fd_ = -1;
    int port_ = 0;
    std::string host_;  // as written in URLs: "127.0.0.1", "[::1]"
    std::string url_;
    SourceAllowList allow_;
    std::vector<std::uint8_t> buffer_;  // one datagram
    std::uint64_t failedReplies_ = 0;
};

}  // namespace vpe::firmware
