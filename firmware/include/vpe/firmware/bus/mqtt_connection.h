// SPDX-License-Identifier: MIT
// MqttConnection: one MQTT v5 client (libmosquitto) driven by the player's own epoll loop, no
// thread of its own. libmosquitto's socket changes with every reconnection, so the connection
// owns an epoll set of its own holding the current socket (readable, and writable while output
// waits): descriptor() is that set, stable for the connection's life, and readable whenever the
// socket needs service. service() does the reading, writing, keepalive and reconnecting; call
// it when descriptor() is readable and on every frame tick.
//
// Connecting never blocks the loop: a numeric address (no resolver), a non-blocking TCP connect
// (mosquitto_connect_async), TLS stepped by the same service calls. A failed attempt or a lost
// connection is retried after 0.1 s, doubling up to 0.5 s; a broker that refuses the
// credentials is asked again every 5 s. (mosquitto_reconnect_delay_set serves libmosquitto's
// own threaded loop, and counts whole seconds: the delays here are the loop's.)
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

struct mosquitto;
struct mosquitto_message;
struct mqtt5__property;

namespace vpe::firmware::bus {

// libmosquitto refused the settings (TLS files it cannot read, out of memory): one line.
class MqttUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct MqttSettings {
    std::string host = "127.0.0.1";  // numeric
    int port = 1883;
    std::string clientId;
    std::string username, password;                                  // empty: none
    std::optional<std::filesystem::path> cafile, certfile, keyfile;  // TLS when cafile is set
    int keepaliveSeconds = 5;  // libmosquitto's least: a dead broker is noticed in 7.5 s
    // Subscribed (QoS 0, no local echo) on every connection.
    std::vector<std::string> subscriptions;
};

class MqttConnection {
public:
    // Reconnection waits 0.1 s, doubling up to this: a node hears a broker that came back
    // within a quarter second, and its light agrees again within a second (the multi-node test
    // measured 1.07 s under a loaded CI run with a half-second ceiling).
    static constexpr std::int64_t kLongestRetryNs = 250'000'000;
    struct Handlers {
        std::function<void()> connected;
        // The broker answered the connection with a refusal (v5 reason code and its text).
        std::function<void(int reasonCode, const std::string& reason)> refused;
        // An attempt that failed, or a connection that dropped (wasConnected).
        std::function<void(const std::string& reason, bool wasConnected)> lost;
        std::function<void(std::string_view topic, std::string_view payload, bool retained)>
            message;
        // The broker's acknowledgement of a QoS 1 publish (v5 reason code; ≥ 0x80: refused).
        std::function<void(int messageId, int reasonCode)> acknowledged;
    };

    // Sets the client up and makes the first attempt (at the first service()). Throws
    // MqttUnavailable.
    MqttConnection(const MqttSettings& settings, Handlers handlers);
    ~MqttConnection();
    MqttConnection(const MqttConnection&) = delete;
    MqttConnection& operator=(const MqttConnection&) = delete;

    // Stable: readable whenever the current socket has something to read or may be written.
    int descriptor() const { return epoll_; }
    // Reads, writes, keepalive, reconnecting. `nowNs`: CLOCK_MONOTONIC.
    void service(std::int64_t nowNs);

    bool connected() const { return state_ == State::kConnected; }
    // A publish: the message id, or empty when not connected or libmosquitto refused it.
    std::optional<int> publish(const std::string& topic, std::string_view payload, int qos,
                               bool retain);

    // "mqtt://127.0.0.1:1883", "mqtts://[::1]:8883"
    std::string endpoint() const;
    // Connections made, and attempts that failed or were refused.
    std::uint64_t connections() const { return connections_; }
    std::uint64_t failedAttempts() const { return failedAttempts_; }

private:
    enum class State { kWaiting, kConnecting, kConnected };

    void attempt(std::int64_t nowNs);
    void retryAfter(std::int64_t delayNs, std::int64_t nowNs);
    void watchSocket(bool force);
    static void onConnect(mosquitto*, void* self, int reason, int flags, const mqtt5__property*);
    static void onDisconnect(mosquitto*, void* self, int reason, const mqtt5__property*);
    static void onMessage(mosquitto*, void* self, const mosquitto_message* message,
                          const mqtt5__property*);
    static void onPublish(mosquitto*, void* self, int messageId, int reason,
                          const mqtt5__property*);

    MqttSettings settings_;
    Handlers handlers_;
    mosquitto* client_ = nullptr;
    int epoll_ = -1;
    int watched_ = -1;  // the socket in epoll_, −1: none
    bool watchedForWriting_ = false;
    State state_ = State::kWaiting;
    bool everAttempted_ = false;
    std::int64_t nextAttemptNs_ = 0;
    std::int64_t retryDelayNs_;
    std::int64_t nowNs_ = 0;  // the current service()'s time, for the callbacks
    bool refusedThisAttempt_ = false;
    std::uint64_t connections_ = 0;
    std::uint64_t failedAttempts_ = 0;
};

}  // namespace vpe::firmware::bus
