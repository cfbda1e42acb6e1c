// SPDX-License-Identifier: MIT
#include "vpe/firmware/bus/light_bus.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "vpe/firmware/loop/show_clock.h"

namespace vpe::firmware::bus {

namespace {

constexpr std::int64_t kNsPerUs = 1000;

// "0.25": the longest wait between connection attempts, as the one-line message says it.
std::string retrySeconds() {
    char text[16];
    std::snprintf(text, sizeof text, "%g",
                  static_cast<double>(MqttConnection::kLongestRetryNs) * 1e-9);
    return text;
}

// A v5 reason code of 0x80 or more is a failure (0x10, "no matching subscribers", is not).
constexpr int kFirstFailureReason = 0x80;

MqttSettings settingsOf(const BusConfig& config) {
    MqttSettings settings;
    settings.host = config.host;
    settings.port = config.port;
    settings.clientId = config.clientId;
    settings.username = config.username;
    settings.password = config.password;
    settings.cafile = config.cafile;
    settings.certfile = config.certfile;
    settings.keyfile = config.keyfile;
    settings.subscriptions = {config.topic(), config.blackoutTopic(), config.commandTopic()};
    return settings;
}

// Names from the network are printed with controls escaped and cut, as OSC's are.
std::string printable(std::string_view text) {
    std::string out;
    for (const char c : text.substr(0, 64)) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned char>(c));
            out += escaped;
        } else {
            out += c;
        }
    }
    return out;
}

std::string seconds(std::int64_t ns) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", static_cast<double>(ns) * 1e-9);
    return text;
}

}  // namespace

LightBus::LightBus(const BusConfig& config, const LightLimits& limits,
                   std::vector<std::string> presetNames, RateLimitedLog::Sink log)
    : config_(config),
      limits_(limits),
      presetNames_(std::move(presetNames)),
      sink_(log),
      refusalLog_(std::move(log)),
      connection_(settingsOf(config),
                  {.connected =
                       [this] {
                           say("bus: connected to " + connection_.endpoint() + " (show \"" +
                               config_.show + "\")");
                           troubleReported_ = false;
                           publishPending(nowNs_);
                       },
                   .refused =
                       [this](int code, const std::string& reason) {
                           if (!troubleReported_) {
                               trouble("bus: the broker at " + connection_.endpoint() +
                                       " refused the connection as \"" + config_.username +
                                       "\": " + reason + " (reason " + std::to_string(code) +
                                       "; check [bus] username and password, and the broker's "
                                       "password file); playing on alone, asking again every 5 s");
                               troubleReported_ = true;
                           }
                       },
                   .lost =
                       [this](const std::string& reason, bool wasConnected) {
                           if (inFlight_) {
                               // Perhaps never arrived: send it again unless newer waits.
                               if (!pending_) {
                                   pending_ = inFlight_;
                               }
                               inFlight_.reset();
                               inFlightId_.reset();
                           }
                           if (wasConnected) {
                               trouble("bus: lost the broker at " + connection_.endpoint() + " (" +
                                       reason + "); playing on with the last state, reconnecting");
                               troubleReported_ = true;
                           } else if (!troubleReported_) {
                               trouble("bus: cannot reach the broker at " + connection_.endpoint() +
                                       " (" + reason +
                                       "); playing on with this node's own light, trying again "
                                       "every " +
                                       retrySeconds() + " s");
                               troubleReported_ = true;
                           }
                       },
                   .message = [this](std::string_view topic, std::string_view payload,
                                     bool) { receive(topic, payload); },
                   .acknowledged =
                       [this](int messageId, int reason) {
                           if (!inFlightId_ || *inFlightId_ != messageId) {
                               return;
                           }
                           if (reason >= kFirstFailureReason) {
                               ++publishRefused_;
                               lastError_ = "bus: the broker refused this node's state";
                               refusalLog_.write(
                                   "bus: the broker refused this node's state on " +
                                       config_.topic() + " (reason " + std::to_string(reason) +
                                       "): user \"" + config_.username +
                                       "\" may not steer the show (the broker's ACL); this "
                                       "node's light is its own until another node's state "
                                       "arrives",
                                   nowNs_);
                           } else {
                               ++published_;
                           }
                           inFlight_.reset();
                           inFlightId_.reset();
                           publishPending(nowNs_);
                       }}) {
    if (!sink_) {
        sink_ = [](const std::string& line) { std::cerr << line << '\n'; };
    }
}

void LightBus::say(const std::string& line) {
    sink_(line);
}

void LightBus::trouble(const std::string& line) {
    lastError_ = line;
    sink_(line);
}

std::string LightBus::description() const {
    return "bus (" + connection_.endpoint() + ", show \"" + config_.show + "\", " +
           busRoleName(config_.role) + " \"" + config_.clientId + "\")";
}

void LightBus::service(std::int64_t nowNs, std::vector<InputEvent>& events) {
    nowNs_ = nowNs;
    collecting_ = &events;
    connection_.service(nowNs);
    collecting_ = nullptr;
    publishPending(nowNs);
}

void LightBus::onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) {
    if (fd == connection_.descriptor()) {
        service(nowNs, events);
    }
}

void LightBus::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    service(nowNs, events);
}

void LightBus::refuse(const std::string& reason, const std::string& problem) {
    ++refused_["bus." + reason];
    lastError_ = "bus: " + problem + " (" + reason + ")";
    refusalLog_.write(lastError_, nowNs_);
}

void LightBus::receive(std::string_view topic, std::string_view payload) {
    if (collecting_ == nullptr) {
        return;
    }
    if (topic == config_.blackoutTopic()) {
        receiveBlackout(payload);
        return;
    }
    if (topic == config_.commandTopic()) {
        receiveInstallCommand(payload);
        return;
    }
    if (topic != config_.topic()) {
        return;  // the subscriptions are these topics alone; anything else is not ours to read
    }
    ++received_;
    auto decoded = decodeLightMessage(payload, limits_);
    if (const auto* refusal = std::get_if<LightMessageRefusal>(&decoded)) {
        refuse(refusal->problem == LightMessageProblem::kMalformed ? "malformed" : "out_of_range",
               config_.topic() + ": " + printable(refusal->reason));
        return;
    }
    const LightMessage& message = std::get<LightMessage>(decoded);
    const std::int64_t aheadNs = message.timeUs * kNsPerUs - realtimeNowNs();
    if (aheadNs > kMaxAheadNs) {
        refuse("clock_ahead", config_.topic() + " from \"" + printable(message.node) + "\": made " +
                                  seconds(aheadNs) +
                                  " s ahead of this node's clock; synchronise the clocks "
                                  "(chrony, docs/multi-node.md)");
        return;
    }
    SharedLight state;
    state.from = message.from;
    state.target = message.target;
    state.moveStartNs = message.fromUs * kNsPerUs;
    if (message.driftUs) {
        state.driftAtNs = *message.driftUs * kNsPerUs;
    }
    state.revisionNs = message.timeUs * kNsPerUs;
    state.steeredBy = InputSource::kBus;
    if (!message.preset.empty()) {
        const auto found = std::find(presetNames_.begin(), presetNames_.end(), message.preset);
        if (found == presetNames_.end()) {
            // The light is still followed: a bundle without that preset keeps its own.
            refuse("unknown_preset", config_.topic() + " from \"" + printable(message.node) +
                                         "\": no preset named \"" + printable(message.preset) +
                                         "\" (" + std::to_string(presetNames_.size()) +
                                         " presets); following the light only");
        } else {
            state.preset = static_cast<int>(found - presetNames_.begin());
        }
    }
    collecting_->push_back({InputSource::kBus, nowNs_, FollowLight{state}});
}

void LightBus::receiveBlackout(std::string_view payload) {
    ++received_;
    auto decoded = decodeBlackoutMessage(payload);
    if (const auto* refusal = std::get_if<LightMessageRefusal>(&decoded)) {
        refuse(refusal->problem == LightMessageProblem::kMalformed ? "malformed" : "out_of_range",
               config_.blackoutTopic() + ": " + printable(refusal->reason));
        return;
    }
    const BlackoutMessage& message = std::get<BlackoutMessage>(decoded);
    if (message.timeUs <= blackoutTimeUs_) {
        return;  // older than the switch this node follows
    }
    blackoutTimeUs_ = message.timeUs;
    if (message.on != blackout_) {
        blackout_ = message.on;
        say(std::string("bus: blackout ") + (blackout_ ? "on" : "off") + " (from \"" +
            printable(message.node) + "\")");
        if (blackoutChanged_) {
            blackoutChanged_(blackout_);
        }
    }
}

void LightBus::receiveInstallCommand(std::string_view payload) {
    ++received_;
    // A command waits in no queue: one older than this was held back and is not run.
    constexpr std::int64_t kMaxCommandAgeUs = 30'000'000;
    auto decoded = decodeInstallCommand(payload, realtimeNowNs() / kNsPerUs, kMaxCommandAgeUs);
    if (const auto* refusal = std::get_if<LightMessageRefusal>(&decoded)) {
        refuse(refusal->problem == LightMessageProblem::kMalformed ? "malformed" : "out_of_range",
               config_.commandTopic() + ": " + printable(refusal->reason));
        return;
    }
    const InstallCommand& command = std::get<InstallCommand>(decoded);
    say(std::string("bus: ") + installActionName(command.action) + " asked by \"" +
        printable(command.node) + "\"");
    if (installCommand_) {
        installCommand_(command);
    }
}

void LightBus::publishInstallProgress(InstallProgress progress) {
    if (!connection_.connected()) {
        return;
    }
    progress.node = config_.clientId;
    connection_.publish(config_.installTopic("progress"), encodeInstallProgress(progress), 1, true);
}

void LightBus::publishInstallImage(const std::string& what, std::string_view png) {
    if (connection_.connected()) {
        connection_.publish(config_.installTopic(what), png, 1, true);
    }
}

void LightBus::publishStatus(NodeStatus status) {
    if (!connection_.connected()) {
        return;
    }
    status.node = config_.clientId;
    status.role = busRoleName(config_.role);
    status.blackout = blackout_;
    if (connection_.publish(config_.statusTopic(), encodeNodeStatus(status), 0, true)) {
        ++statusPublished_;
    }
}

void LightBus::offer(const SharedLight& state, std::int64_t nowNs) {
    if (config_.role != BusRole::kController) {
        if (!playerRoleReported_) {
            say("bus: role player: this node's own inputs steer its light only (a controller "
                "publishes to the show)");
            playerRoleReported_ = true;
        }
        return;
    }
    LightMessage message;
    message.node = config_.clientId;
    message.timeUs = state.revisionNs / kNsPerUs;
    message.target = state.target;
    message.from = state.from;
    message.fromUs = state.moveStartNs / kNsPerUs;
    if (state.driftAtNs) {
        message.driftUs = *state.driftAtNs / kNsPerUs;
    }
    if (state.preset >= 0 && static_cast<std::size_t>(state.preset) < presetNames_.size()) {
        message.preset = presetNames_[static_cast<std::size_t>(state.preset)];
    }
    message.source = inputSourceName(state.steeredBy);
    pending_ = std::move(message);
    publishPending(nowNs);
}

void LightBus::publishPending(std::int64_t nowNs) {
    if (!pending_ || inFlight_ || !connection_.connected() ||
        (lastPublishNs_ != 0 && nowNs - lastPublishNs_ < kMinPublishIntervalNs)) {
        return;
    }
    LightMessage message = *pending_;
    message.seq = ++seq_;
    const std::optional<int> id =
        connection_.publish(config_.topic(), encodeLightMessage(message), 1, true);
    if (!id || !connection_.connected()) {
        return;  // kept pending: it goes once the broker is back
    }
    inFlight_ = std::move(message);
    inFlightId_ = id;
    pending_.reset();
    lastPublishNs_ = nowNs;
}

std::map<std::string, std::uint64_t> LightBus::refusals() const {
    return refused_;
}

std::map<std::string, std::uint64_t> LightBus::counters() const {
    return {{"bus.connections", connection_.connections()},
            {"bus.failed_attempts", connection_.failedAttempts()},
            {"bus.received", received_},
            {"bus.published", published_},
            {"bus.publish_refused", publishRefused_},
            {"bus.status_published", statusPublished_},
            {"bus.connected", connection_.connected() ? 1u : 0u}};
}

}  // namespace vpe::firmware::bus
