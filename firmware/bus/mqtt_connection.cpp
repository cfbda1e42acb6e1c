// SPDX-License-Identifier: MIT
// MqttConnection: libmosquitto's client stepped by the player's loop (mosquitto_loop with a zero
// timeout whenever its socket is ready or a tick comes), reconnecting on its own.
#include "vpe/firmware/bus/mqtt_connection.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <mosquitto.h>
#include <mqtt_protocol.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <unistd.h>

namespace vpe::firmware::bus {

namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kFirstRetryNs = 100 * kMs;
// A broker that refuses the credentials will refuse them again soon: ask less often.
constexpr std::int64_t kRefusedRetryNs = 5'000 * kMs;
// Packets handled per service(): a flood waits for the next turn of the loop (the descriptor
// stays readable), so the bus cannot starve the frames.
constexpr int kMaxPacketsPerService = 512;

// mosquitto_lib_init is process-wide and not thread-safe: once, before the first client.
void initialiseLibrary() {
    struct Library {
        Library() { mosquitto_lib_init(); }
        ~Library() { mosquitto_lib_cleanup(); }
    };
    static const Library library;
}

std::string describe(int code) {
    if (code == MOSQ_ERR_ERRNO) {
        return std::strerror(errno);
    }
    return mosquitto_strerror(code);
}

std::string hostForUrl(const std::string& host) {
    return host.find(':') == std::string::npos ? host : "[" + host + "]";
}

int bytesWaiting(int socket) {
    int waiting = 0;
    return ::ioctl(socket, FIONREAD, &waiting) == 0 ? waiting : 0;
}

}  // namespace

MqttConnection::MqttConnection(const MqttSettings& settings, Handlers handlers)
    : settings_(settings), handlers_(std::move(handlers)), retryDelayNs_(kFirstRetryNs) {
    initialiseLibrary();
    const auto unavailable = [&](const std::string& problem) {
        return MqttUnavailable(endpoint() + ": " + problem);
    };
    epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
    if (epoll_ < 0) {
        throw unavailable(std::string("epoll_create1: ") + std::strerror(errno));
    }
    // A clean start: the subscription is made again on every connection, and the broker
    // keeps no queue for a node that is away (it takes the retained state when it is back).
    client_ = mosquitto_new(settings_.clientId.c_str(), true, this);
    if (client_ == nullptr) {
        ::close(epoll_);
        throw unavailable(std::string("cannot create a client (") + std::strerror(errno) + ")");
    }
    const auto check = [&](int code, const char* what) {
        if (code != MOSQ_ERR_SUCCESS) {
            mosquitto_destroy(client_);
            ::close(epoll_);
            throw unavailable(std::string(what) + ": " + describe(code));
        }
    };
    check(mosquitto_int_option(client_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V5), "MQTT v5");
    if (!settings_.username.empty()) {
        check(mosquitto_username_pw_set(
                  client_, settings_.username.c_str(),
                  settings_.password.empty() ? nullptr : settings_.password.c_str()),
              "credentials");
    }
    if (settings_.cafile) {
        check(mosquitto_tls_set(client_, settings_.cafile->c_str(), nullptr,
                                settings_.certfile ? settings_.certfile->c_str() : nullptr,
                                settings_.keyfile ? settings_.keyfile->c_str() : nullptr, nullptr),
              "TLS files");
    }
    mosquitto_connect_v5_callback_set(client_, &MqttConnection::onConnect);
    mosquitto_disconnect_v5_callback_set(client_, &MqttConnection::onDisconnect);
    mosquitto_message_v5_callback_set(client_, &MqttConnection::onMessage);
    mosquitto_publish_v5_callback_set(client_, &MqttConnection::onPublish);
}

MqttConnection::~MqttConnection() {
    handlers_ = {};  // the owner is going away: nothing more to tell it
    if (state_ == State::kConnected) {
        // A clean goodbye, so the broker does not wait out the keepalive; best effort.
        mosquitto_disconnect(client_);
        mosquitto_loop_write(client_, 1);
    }
    mosquitto_destroy(client_);
    ::close(epoll_);
}

std::string MqttConnection::endpoint() const {
    return std::string(settings_.cafile ? "mqtts://" : "mqtt://") + hostForUrl(settings_.host) +
           ":" + std::to_string(settings_.port);
}

void MqttConnection::retryAfter(std::int64_t delayNs, std::int64_t nowNs) {
    state_ = State::kWaiting;
    nextAttemptNs_ = nowNs + delayNs;
    watchSocket(true);
}

void MqttConnection::attempt(std::int64_t nowNs) {
    refusedThisAttempt_ = false;
    state_ = State::kConnecting;
    // The first time connect_async (it records the broker); later reconnect_async, which also
    // closes whatever socket an abandoned attempt left.
    const int code = everAttempted_
                         ? mosquitto_reconnect_async(client_)
                         : mosquitto_connect_async(client_, settings_.host.c_str(), settings_.port,
                                                   settings_.keepaliveSeconds);
    everAttempted_ = true;
    if (code != MOSQ_ERR_SUCCESS) {
        const std::string reason = describe(code);
        ++failedAttempts_;
        const std::int64_t delay = retryDelayNs_;
        retryDelayNs_ = std::min(retryDelayNs_ * 2, kLongestRetryNs);
        retryAfter(delay, nowNs);
        if (handlers_.lost) {
            handlers_.lost(reason, false);
        }
        return;
    }
    watchSocket(true);
}

void MqttConnection::watchSocket(bool force) {
    const int socket = state_ == State::kWaiting ? -1 : mosquitto_socket(client_);
    const bool writing = socket >= 0 && mosquitto_want_write(client_);
    if (!force && socket == watched_ && writing == watchedForWriting_) {
        return;
    }
    if (watched_ >= 0) {
        // Fails harmlessly when libmosquitto already closed it (closing drops it from the set).
        ::epoll_ctl(epoll_, EPOLL_CTL_DEL, watched_, nullptr);
    }
    watched_ = -1;
    if (socket < 0) {
        return;
    }
    epoll_event event{};
    event.events = EPOLLIN | (writing ? EPOLLOUT : 0u);
    event.data.fd = socket;
    if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, socket, &event) == 0) {
        watched_ = socket;
        watchedForWriting_ = writing;
    }
}

void MqttConnection::service(std::int64_t nowNs) {
    nowNs_ = nowNs;
    if (state_ == State::kWaiting) {
        if (nowNs < nextAttemptNs_) {
            return;
        }
        attempt(nowNs);
        if (state_ == State::kWaiting) {
            return;
        }
    }
    for (int packet = 0; packet < kMaxPacketsPerService; ++packet) {
        // A zero timeout: select() over the one socket, then what it is ready for (TLS
        // handshake steps included), then the keepalive. Never waits.
        const int code = mosquitto_loop(client_, 0, 1);
        const int socket = mosquitto_socket(client_);
        if (socket < 0 || state_ == State::kWaiting) {
            // Closed: libmosquitto reported it through onDisconnect (which scheduled the
            // retry), or, for an error it does not report, here.
            if (state_ != State::kWaiting) {
                const bool wasConnected = state_ == State::kConnected;
                ++failedAttempts_;
                retryAfter(retryDelayNs_, nowNs);
                if (handlers_.lost) {
                    handlers_.lost(describe(code == MOSQ_ERR_SUCCESS ? MOSQ_ERR_NO_CONN : code),
                                   wasConnected);
                }
            }
            return;
        }
        // One packet per call (libmosquitto reads exactly one): go on while bytes wait.
        if (code != MOSQ_ERR_SUCCESS || bytesWaiting(socket) == 0) {
            break;
        }
    }
    watchSocket(false);
}

std::optional<int> MqttConnection::publish(const std::string& topic, std::string_view payload,
                                           int qos, bool retain) {
    if (state_ != State::kConnected) {
        return std::nullopt;
    }
    int messageId = 0;
    const int code =
        mosquitto_publish_v5(client_, &messageId, topic.c_str(), static_cast<int>(payload.size()),
                             payload.data(), qos, retain, nullptr);
    if (code != MOSQ_ERR_SUCCESS) {
        return std::nullopt;
    }
    // libmosquitto writes at once outside its callbacks; what the socket did not take (or what
    // was queued from a callback) goes when the loop finds the socket writable.
    watchSocket(false);
    return messageId;
}

void MqttConnection::onConnect(mosquitto*, void* self, int reason, int, const mqtt5__property*) {
    auto* connection = static_cast<MqttConnection*>(self);
    if (reason != 0) {
        // The broker closes the connection after a refusal; onDisconnect schedules the retry.
        ++connection->failedAttempts_;
        connection->refusedThisAttempt_ = true;
        if (connection->handlers_.refused) {
            connection->handlers_.refused(reason, mosquitto_reason_string(reason));
        }
        return;
    }
    connection->state_ = State::kConnected;
    connection->retryDelayNs_ = kFirstRetryNs;
    ++connection->connections_;
    for (const std::string& topic : connection->settings_.subscriptions) {
        // QoS 0: the newest state is all that matters, and a node that was away takes the
        // retained one on this subscription. No local: a node's own states do not come back.
        mosquitto_subscribe_v5(connection->client_, nullptr, topic.c_str(), 0,
                               MQTT_SUB_OPT_NO_LOCAL, nullptr);
    }
    if (connection->handlers_.connected) {
        connection->handlers_.connected();
    }
}

void MqttConnection::onDisconnect(mosquitto*, void* self, int reason, const mqtt5__property*) {
    auto* connection = static_cast<MqttConnection*>(self);
    if (connection->state_ == State::kWaiting) {
        return;
    }
    const bool wasConnected = connection->state_ == State::kConnected;
    const bool refused = connection->refusedThisAttempt_;
    if (!wasConnected && !refused) {
        ++connection->failedAttempts_;
    }
    std::int64_t delay = refused ? kRefusedRetryNs : connection->retryDelayNs_;
    if (!refused && !wasConnected) {
        connection->retryDelayNs_ = std::min(connection->retryDelayNs_ * 2, kLongestRetryNs);
    }
    if (wasConnected) {
        delay = 0;  // the broker was there a moment ago: try again at once
    }
    connection->retryAfter(delay, connection->nowNs_);
    if (!refused && connection->handlers_.lost) {
        connection->handlers_.lost(describe(reason), wasConnected);
    }
}

void MqttConnection::onMessage(mosquitto*, void* self, const mosquitto_message* message,
                               const mqtt5__property*) {
    auto* connection = static_cast<MqttConnection*>(self);
    if (connection->handlers_.message && message->topic != nullptr) {
        connection->handlers_.message(
            message->topic,
            std::string_view(static_cast<const char*>(message->payload),
                             static_cast<std::size_t>(std::max(message->payloadlen, 0))),
            message->retain);
    }
}

void MqttConnection::onPublish(mosquitto*, void* self, int messageId, int reason,
                               const mqtt5__property*) {
    auto* connection = static_cast<MqttConnection*>(self);
    if (connection->handlers_.acknowledged) {
        connection->handlers_.acknowledged(messageId, reason);
    }
}

}  // namespace vpe::firmware::bus
