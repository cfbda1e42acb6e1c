// SPDX-License-Identifier: MIT
// LightBus: one virtual light shared by the nodes of a show over an MQTT broker (docs/
// multi-node.md, proto/BUS.md). As an input it turns the retained state on vpe/<show>/light
// into FollowLight events (another node's light, taken when newer than this node's); as a
// publisher it sends what this node's own inputs did, when its role is controller: retained,
// QoS 1 with one message in flight (the broker acknowledges each state, so a refusal by its ACL
// is seen, and a state superseded while waiting is never sent), at most 60 a second, the newest
// always last. Refused messages are counted per reason and logged rate-limited; a broker that
// is absent, goes away or refuses the credentials is logged once, and the node plays on.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/bus/bus_config.h"
#include "vpe/firmware/bus/install_message.h"
#include "vpe/firmware/bus/light_message.h"
#include "vpe/firmware/bus/mqtt_connection.h"
#include "vpe/firmware/bus/node_status.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/light/shared_light_publisher.h"
#include "vpe/firmware/loop/rate_limited_log.h"

namespace vpe::firmware::bus {

class LightBus final : public InputDevice, public SharedLightPublisher {
public:
    // Other nodes' states at most this far ahead of this node's clock are taken; beyond, the
    // clocks are not synchronised (chrony) and the state is refused as clock_ahead.
    static constexpr std::int64_t kMaxAheadNs = 2'000'000'000;
    // At most this many states a second leave the node.
    static constexpr std::int64_t kMinPublishIntervalNs = 1'000'000'000 / 60;

    // limits: the light rig's (distance resolved); presetNames: the bundle's, in index order.
    // `log` gets every line ("bus: …"); empty: stderr. Throws MqttUnavailable.
    LightBus(const BusConfig& config, const LightLimits& limits,
             std::vector<std::string> presetNames, RateLimitedLog::Sink log = {});

    // "bus (mqtt://127.0.0.1:1883, show \"foyer\", controller \"vpe-pi-left\")"
    std::string description() const override;
    std::vector<int> pollDescriptors() const override { return {connection_.descriptor()}; }
    void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) override;
    void onTick(std::int64_t nowNs, std::vector<InputEvent>& events) override;
    // "bus.malformed", "bus.out_of_range", "bus.clock_ahead", "bus.unknown_preset".
    std::map<std::string, std::uint64_t> refusals() const override;
    // "bus.connections", "bus.failed_attempts", "bus.received", "bus.published",
    // "bus.publish_refused", "bus.connected" (1 while connected).
    std::map<std::string, std::uint64_t> counters() const override;

    void offer(const SharedLight& state, std::int64_t nowNs) override;

    // A reloaded bundle: its presets and the rig's re-derived limits.
    void setPresetNames(std::vector<std::string> names) { presetNames_ = std::move(names); }
    void setLimits(const LightLimits& limits) { limits_ = limits; }

    // This node's status on vpe/<show>/status/<client id>, retained, QoS 0 (the next one
    // supersedes it a second later); node, role and blackout are filled in here. Nothing when
    // the broker is away.
    void publishStatus(NodeStatus status);
    // Called when the show's blackout switch (vpe/<show>/blackout) changes.
    void onBlackout(std::function<void(bool)> callback) { blackoutChanged_ = std::move(callback); }
    bool blackout() const { return blackout_; }
    // Called with each valid command on vpe/<show>/command/<client id> (a scan or a radiometric
    // capture asked by a controller; proto/BUS.md, "Install steps"). Refused ones are counted
    // and logged as the light's are.
    void onInstallCommand(std::function<void(const InstallCommand&)> callback) {
        installCommand_ = std::move(callback);
    }
    // The capture's progress on vpe/<show>/install/<client id>/progress, retained, QoS 1; node
    // filled in here. Nothing when the broker is away.
    void publishInstallProgress(InstallProgress progress);
    // An image (a small PNG) on vpe/<show>/install/<client id>/<what>, retained, QoS 1.
    void publishInstallImage(const std::string& what, std::string_view png);
    // Services the connection alone (reading, writing, keepalive) while the loop is busy with a
    // capture: messages are taken as onTick would take them, into `events`.
    void serviceNow(std::int64_t nowNs, std::vector<InputEvent>& events) { service(nowNs, events); }

    // The newest problem this bus logged (a refusal, a lost broker), empty: none.
    const std::string& lastError() const { return lastError_; }

    bool connected() const { return connection_.connected(); }
    const BusConfig& config() const { return config_; }

private:
    void service(std::int64_t nowNs, std::vector<InputEvent>& events);
    void receive(std::string_view topic, std::string_view payload);
    void refuse(const std::string& reason, const std::string& problem);
    void publishPending(std::int64_t nowNs);
    void say(const std::string& line);
    void trouble(const std::string& line);
    void receiveBlackout(std::string_view payload);
    void receiveInstallCommand(std::string_view payload);

    BusConfig config_;
    LightLimits limits_;
    std::vector<std::string> presetNames_;
    RateLimitedLog::Sink sink_;
    RateLimitedLog refusalLog_;
    std::vector<InputEvent>* collecting_ = nullptr;  // during service(): where events go
    std::int64_t nowNs_ = 0;
    std::map<std::string, std::uint64_t> refused_;
    std::uint64_t received_ = 0, published_ = 0, publishRefused_ = 0;
    std::uint64_t seq_ = 0;
    std::optional<LightMessage> pending_;   // the newest state not yet sent
    std::optional<LightMessage> inFlight_;  // sent, not yet acknowledged
    std::optional<int> inFlightId_;
    std::int64_t lastPublishNs_ = 0;
    bool troubleReported_ = false;  // a connection problem was logged since the last success
    bool playerRoleReported_ = false;
    std::uint64_t statusPublished_ = 0;
    bool blackout_ = false;
    std::int64_t blackoutTimeUs_ = 0;  // the newest blackout message taken
    std::function<void(bool)> blackoutChanged_;
    std::function<void(const InstallCommand&)> installCommand_;
    std::string lastError_;
    // Last: it calls back into the members above while it is alive.
    MqttConnection connection_;
};

}  // namespace vpe::firmware::bus
