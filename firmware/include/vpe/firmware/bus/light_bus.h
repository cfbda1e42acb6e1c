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
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpe/firmware/bus/bus_config.h"
#include "vpe/firmware/bus/light_message.h"
#include "vpe/firmware/bus/mqtt_connection.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/light/light_config.h"
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

    bool connected() const { return connection_.connected(); }
    const BusConfig& config() const { return config_; }

private:
    void service(std::int64_t nowNs, std::vector<InputEvent>& events);
    void receive(std::string_view topic, std::string_view payload);
    void refuse(const std::string& reason, const std::string& problem);
    void publishPending(std::int64_t nowNs);
    void say(const std::string& line);

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
    // Last: it calls back into the members above while it is alive.
    MqttConnection connection_;
};

}  // namespace vpe::firmware::bus
