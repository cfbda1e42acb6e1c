// SPDX-License-Identifier: MIT
#include "vpe/firmware/player/input_setup.h"

#include <functional>
#include <utility>
#include <variant>

#include "vpe/firmware/bus/light_bus.h"
#include "vpe/firmware/knobs/gpio_knobs.h"
#include "vpe/firmware/osc/osc_server.h"
#include "vpe/firmware/player/player_log.h"
#include "vpe/firmware/player/replay_input.h"
#include "vpe/firmware/tracking/libcamera_lamp.h"
#include "vpe/proto/pinhole_camera.h"

namespace vpe::firmware {

namespace {

std::vector<std::string> presetNamesOf(const proto::BundleView& view) {
    std::vector<std::string> names;
    for (const auto& preset : view.presets()) {
        names.emplace_back(preset.name);
    }
    return names;
}

// A lamp mapped by the bundle's camera follows each reloaded bundle's camera (and light
// sphere); a new bundle without one, or with one the stream cannot use, leaves the lamp on the
// previous model, logged. `apply` hands the new map to the device.
void followBundleCamera(Player& player, const CameraConfig& camera, const InputSettings& settings,
                        std::function<void(LampDirectionMap)> apply) {
    const Player* observed = &player;
    player.onBundleReloaded([observed, camera, settings, apply = std::move(apply)] {
        const proto::BundleView& bundle = observed->bundle();
        if (!bundle.camera()) {
            playerLog(
                "camera: the new bundle carries no camera; the lamp keeps the previous "
                "bundle's");
            return;
        }
        try {
            LampDirectionMap map = lampDirectionFor(camera, settings, bundle);
            playerLog("camera: the lamp follows " + describeLampDirectionMap(map));
            apply(std::move(map));
        } catch (const BoardConfigError& error) {
            playerLog(std::string(error.what()) + "; the lamp keeps the previous bundle's camera");
        }
    });
}

// The shared light: an input (other nodes' states) and the publisher of this node's own.
bus::LightBus* addBus(Player& player, const bus::BusConfig& config) {
    try {
        auto light = std::make_unique<bus::LightBus>(config, player.rig().limits(),
                                                     presetNamesOf(player.bundle()), playerLog);
        bus::LightBus* raw = light.get();
        playerLog(raw->description());
        const Player* observed = &player;
        player.onBundleReloaded([raw, observed] {
            raw->setPresetNames(presetNamesOf(observed->bundle()));
            raw->setLimits(observed->rig().limits());
        });
        player.setPublisher(raw);
        // The control page's side (proto/BUS.md, "Node status", "Blackout").
        Player* steered = &player;
        raw->onBlackout([steered](bool on) { steered->setBlackout(on); });
        player.everySecond([raw, steered] {
            bus::NodeStatus status;
            status.timeUs = realtimeNowNs() / 1000;
            status.fps = steered->lastWindow().fps;
            status.frameP99Ms = steered->lastWindow().frameP99Ms;
            status.skipped = static_cast<std::uint64_t>(steered->lastWindow().skipped);
            status.socTemperatureC = bus::readSocTemperature();
            status.bundle = steered->bundleName();
            status.bundleChecksum = steered->bundleChecksum();
            status.activeInput = inputSourceName(steered->rig().activeSource());
            status.uptimeS = steered->uptimeSeconds();
            // The newer of the player's and the bus's problems is not known: the player's
            // (frames, reloads) matter more on site.
            status.lastError =
                steered->lastError().empty() ? raw->lastError() : steered->lastError();
            status.watchdog = steered->watchdogState();
            status.light = steered->rig().current();
            status.limits = steered->rig().limits();
            status.presets = presetNamesOf(steered->bundle());
            status.preset = steered->presetName();
            raw->publishStatus(std::move(status));
        });
        player.addInput(std::move(light));
        return raw;
    } catch (const bus::MqttUnavailable& error) {
        playerLog(std::string("bus: ") + error.what() + "; playing without it");
    }
    return nullptr;
}

}  // namespace

ShowClock showClockFor(const InputSettings& settings) {
    return ShowClock(settings.bus && settings.bus->enabled ? ShowClock::Kind::kRealtime
                                                           : ShowClock::Kind::kMonotonic);
}

LampDirectionMap lampDirectionFor(const CameraConfig& camera, const InputSettings& settings,
                                  const proto::BundleView& bundle) {
    std::optional<proto::PinholeCamera> bundleCamera;
    if (bundle.camera()) {
        bundleCamera = proto::cameraOf(*bundle.camera());
    }
    return lampDirectionMapOf(camera, bundleCamera, Player::sphereOf(bundle), settings.light,
                              settings.source);
}

InputSettings readInputSettings(const BoardConfig& board) {
    InputSettings settings;
    settings.light = board.light;
    settings.source = board.source;
    if (const toml::table* gpio = board.section("gpio")) {
        settings.knobs = knobs::parseKnobsConfig(*gpio, board.source);
    }
    if (const toml::table* camera = board.section("camera")) {
        settings.camera = parseCameraConfig(*camera, board.source);
    }
    if (const toml::table* osc = board.section("osc")) {
        settings.osc = parseOscConfig(osc, board.source);
    }
    if (const toml::table* bus = board.section("bus")) {
        settings.bus = bus::parseBusConfig(bus, board.source);
    }
    return settings;
}

OscLimits oscLimitsOf(const LightLimits& light) {
    OscLimits limits;
    limits.azimuthDeg = light.azimuthDeg;
    limits.elevationDeg = light.elevationDeg;
    if (light.distanceM) {
        limits.distanceM = *light.distanceM;
    }
    return limits;
}

bus::LightBus* addInputs(Player& player, const InputSettings& settings,
                         const PlayerOptions& options) {
    // The bus is not the board's hardware: a replayed node shares its light like a live one.
    bus::LightBus* lightBus = nullptr;
    if (settings.bus && settings.bus->enabled) {
        lightBus = addBus(player, *settings.bus);
    }
    if (options.replay) {
        // A replay stands in for every input: a session reproduced exactly, whatever the
        // machine has attached.
        ReplayDecoders decoders;
        decoders.knobs = settings.knobs;
        decoders.camera = settings.camera;
        if (settings.camera) {
            try {
                decoders.lampDirection =
                    lampDirectionFor(*settings.camera, settings, player.bundle());
            } catch (const BoardConfigError& error) {
                // A disabled camera is needed only by camera events, and the replay refuses
                // those without a map.
                if (settings.camera->enabled) {
                    throw;
                }
            }
        }
        decoders.oscLimits = oscLimitsOf(player.rig().limits());
        decoders.presetNames = presetNamesOf(player.bundle());
        auto replay =
            std::make_unique<ReplayInput>(*options.replay, readReplayFile(*options.replay),
                                          decoders, options.replayLoop, monotonicNowNs());
        ReplayInput* raw = replay.get();
        playerLog(raw->description());
        player.addInput(std::move(replay));
        if (decoders.lampDirection &&
            std::holds_alternative<CameraLampModel>(*decoders.lampDirection)) {
            followBundleCamera(player, *settings.camera, settings, [raw](LampDirectionMap map) {
                raw->setLampDirection(std::move(map));
            });
        }
        if (options.frames == 0) {
            player.stopWhen([raw] { return raw->finished(); }, "replay");
        }
        return lightBus;
    }
    if (settings.knobs && settings.knobs->enabled) {
        try {
            auto knobs = std::make_unique<knobs::GpioKnobs>(*settings.knobs);
            playerLog(knobs->description());
            player.addInput(std::move(knobs));
        } catch (const knobs::KnobsUnavailable& error) {
            playerLog(std::string("knobs: ") + error.what() + "; playing without them");
        }
    }
    if (settings.camera && settings.camera->enabled) {
        // Resolved before the camera is opened: a board that cannot map the lamp is refused
        // whether or not a camera is attached.
        const LampDirectionMap map = lampDirectionFor(*settings.camera, settings, player.bundle());
        try {
            auto camera = std::make_unique<LibcameraLamp>(*settings.camera, map);
            LibcameraLamp* raw = camera.get();
            playerLog(camera->description() + ", the lamp mapped by " +
                      describeLampDirectionMap(map));
            player.addInput(std::move(camera));
            if (std::holds_alternative<CameraLampModel>(map)) {
                followBundleCamera(player, *settings.camera, settings, [raw](LampDirectionMap m) {
                    raw->setDirectionMap(std::move(m));
                });
            }
        } catch (const CameraUnavailable& error) {
            playerLog(std::string("camera: ") + error.what() + "; playing without it");
        }
    }
    if (settings.osc && settings.osc->enabled) {
        try {
            auto server = std::make_unique<OscServer>(
                *settings.osc, oscLimitsOf(player.rig().limits()), playerLog);
            server->dispatcher().setPresetNames(presetNamesOf(player.bundle()));
            const Player* observed = &player;
            server->setStatusProvider([observed] {
                OscStatus status;
                const FrameReport& report = observed->report();
                status.framesRendered = report.frames;
                status.fps = report.fps();
                const SphericalPosition& light = observed->rig().current();
                status.azimuthDeg = light.azimuthDeg;
                status.elevationDeg = light.elevationDeg;
                status.distanceM = light.distanceM;
                const auto& presets = observed->bundle().presets();
                const auto index = static_cast<std::size_t>(observed->rig().preset());
                status.preset = index < presets.size() ? std::string(presets[index].name) : "";
                status.activeInput = inputSourceName(observed->rig().activeSource());
                return status;
            });
            OscDispatcher* dispatcher = &server->dispatcher();
            player.onBundleReloaded([dispatcher, observed] {
                dispatcher->setPresetNames(presetNamesOf(observed->bundle()));
            });
            playerLog(server->description());
            player.addInput(std::move(server));
        } catch (const OscUnavailable& error) {
            playerLog(std::string("osc: ") + error.what() + "; playing without it");
        }
    }
    return lightBus;
}

}  // namespace vpe::firmware
