// SPDX-License-Identifier: MIT
#include "vpe/firmware/light/light_rig.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace vpe::firmware {

namespace {

constexpr double kNsPerSecond = 1e9;

double secondsBetween(std::int64_t fromNs, std::int64_t toNs) {
    return static_cast<double>(toNs - fromNs) / kNsPerSecond;
}

// Full-circle azimuth limits wrap; narrower ones clamp.
bool wraps(const LightLimits& limits) {
    return limits.azimuthDeg.second - limits.azimuthDeg.first >= 360.0;
}

LightLimits resolved(LightLimits limits, const LightSphere& sphere) {
    if (!limits.distanceM) {
        limits.distanceM = std::pair{0.5 * sphere.objectRadius(), 4.0 * sphere.objectRadius()};
    }
    return limits;
}

SphericalPosition initialOf(const LightConfig& config, const LightSphere& sphere) {
    return {config.initialAzimuthDeg, config.initialElevationDeg,
            config.initialDistanceM.value_or(2.0 * sphere.objectRadius())};
}

}  // namespace

LightRig::LightRig(const LightConfig& light, const IdleConfig& idle, const LightSphere& sphere,
                   int presetCount, std::int64_t nowNs)
    : config_(light),
      drift_(idle),
      idleConfig_(idle),
      sphere_(sphere),
      limits_(resolved(light.limits, sphere)),
      moveStartNs_(nowNs),
      presetCount_(std::max(presetCount, 1)),
      lastAdvanceNs_(nowNs) {
    initial_ = from_ = target_ = current_ = clamped(initialOf(config_, sphere_));
    if (idleConfig_.enabled) {
        driftAtNs_ = nowNs + static_cast<std::int64_t>(idleConfig_.quietSeconds * kNsPerSecond);
    }
}

SphericalPosition LightRig::clamped(SphericalPosition p) const {
    if (wraps(limits_)) {
        p.azimuthDeg = std::remainder(p.azimuthDeg, 360.0);
    } else {
        p.azimuthDeg =
            std::clamp(p.azimuthDeg, limits_.azimuthDeg.first, limits_.azimuthDeg.second);
    }
    p.elevationDeg =
        std::clamp(p.elevationDeg, limits_.elevationDeg.first, limits_.elevationDeg.second);
    p.distanceM = std::clamp(p.distanceM, limits_.distanceM->first, limits_.distanceM->second);
    return p;
}

SphericalPosition LightRig::movedAt(std::int64_t nowNs) const {
    if (config_.smoothingSeconds <= 0) {
        return target_;
    }
    if (nowNs <= moveStartNs_) {
        return from_;
    }
    // The exponential approach in closed form: the same light at a given time however many
    // frames were drawn on the way (a node at 50 Hz and one at 60 Hz agree).
    const double reached =
        1.0 - std::exp(-secondsBetween(moveStartNs_, nowNs) / config_.smoothingSeconds);
    double dAz = target_.azimuthDeg - from_.azimuthDeg;
    if (wraps(limits_)) {
        dAz = std::remainder(dAz, 360.0);
    }
    return clamped({from_.azimuthDeg + reached * dAz,
                    from_.elevationDeg + reached * (target_.elevationDeg - from_.elevationDeg),
                    from_.distanceM + reached * (target_.distanceM - from_.distanceM)});
}

SphericalPosition LightRig::lightAt(std::int64_t nowNs) const {
    if (!driftingAt(nowNs)) {
        return movedAt(nowNs);
    }
    return clamped(drift_.position(movedAt(*driftAtNs_), secondsBetween(*driftAtNs_, nowNs),
                                   drift_.phaseAt(nowNs)));
}

void LightRig::touched(std::int64_t eventNs) {
    // Strictly newer than anything seen, so that other nodes take it even when a state from
    // a node whose clock runs slightly ahead arrived first.
    revisionNs_ = std::max(eventNs, revisionNs_ + 1);
}

template <typename Aim>
void LightRig::steer(InputSource source, std::int64_t eventNs, Aim aim) {
    // The move starts at the event (plus the lead), or at the frame already shown when that
    // is later: the light continues from what is on screen.
    const std::int64_t startNs = std::max({eventNs + moveLeadNs_, lastAdvanceNs_, moveStartNs_});
    const SphericalPosition here = lightAt(startNs);
    // Steering resumes from where the drift brought the light (relative knob turns too).
    const SphericalPosition base = driftingAt(startNs) ? here : target_;
    from_ = here;
    target_ = clamped(aim(base));
    moveStartNs_ = startNs;
    driftAtNs_.reset();
    if (idleConfig_.enabled) {
        driftAtNs_ = startNs + static_cast<std::int64_t>(idleConfig_.quietSeconds * kNsPerSecond);
    }
    steeredBy_ = source;
    touched(startNs);
}

void LightRig::follow(const SharedLight& state) {
    if (state.revisionNs <= revisionNs_) {
        ++staleStates_;  // an echo of this node's own state, or one it has already superseded
        return;
    }
    from_ = clamped(state.from);
    target_ = clamped(state.target);
    moveStartNs_ = state.moveStartNs;
    driftAtNs_ = state.driftAtNs;
    if (state.preset >= 0 && state.preset < presetCount_) {
        preset_ = state.preset;
    }
    revisionNs_ = state.revisionNs;
    steeredBy_ = InputSource::kBus;
}

bool LightRig::apply(const InputEvent& event) {
    bool accepted = true;
    const std::int64_t t = event.timestampNs;
    std::visit(
        [&](const auto& action) {
            using Action = std::decay_t<decltype(action)>;
            if constexpr (std::is_same_v<Action, TurnLight>) {
                steer(event.source, t, [&](SphericalPosition p) {
                    p.azimuthDeg += action.azimuthDeg;
                    p.elevationDeg += action.elevationDeg;
                    p.distanceM += action.distanceM;
                    return p;
                });
            } else if constexpr (std::is_same_v<Action, AimLight>) {
                steer(event.source, t, [&](SphericalPosition p) {
                    p.azimuthDeg = action.azimuthDeg.value_or(p.azimuthDeg);
                    p.elevationDeg = action.elevationDeg.value_or(p.elevationDeg);
                    p.distanceM = action.distanceM.value_or(p.distanceM);
                    return p;
                });
            } else if constexpr (std::is_same_v<Action, PlaceLight>) {
                steer(event.source, t, [&](const SphericalPosition&) {
                    return sphere_.fromPosition(action.position);
                });
            } else if constexpr (std::is_same_v<Action, ResetLight>) {
                steer(event.source, t, [&](const SphericalPosition&) { return initial_; });
            } else if constexpr (std::is_same_v<Action, SelectPreset>) {
                // Choosing a material is not steering: the light keeps what it was doing.
                const int before = preset_;
                if (action.relative) {
                    preset_ =
                        ((preset_ + action.value) % presetCount_ + presetCount_) % presetCount_;
                } else if (action.value >= 0 && action.value < presetCount_) {
                    preset_ = action.value;
                } else {
                    accepted = false;
                }
                // The player adopting the renderer's preset (source idle) is no change to share.
                if (preset_ != before && event.source != InputSource::kIdle) {
                    touched(t);
                }
            } else if constexpr (std::is_same_v<Action, ReleaseLight>) {
                // Only the steering source can let go; the drift starts at once, since the
                // source already waited (a lost lamp holds for its hold time first).
                const std::int64_t at = std::max({t + moveLeadNs_, lastAdvanceNs_, moveStartNs_});
                if (event.source == steeredBy_ && idleConfig_.enabled && !driftingAt(at)) {
                    driftAtNs_ = at;
                    touched(at);
                }
            } else if constexpr (std::is_same_v<Action, FollowLight>) {
                follow(action.state);
            }
        },
        event.action);
    if (accepted) {
        lastEventNs_ = std::max(lastEventNs_, t);
    }
    return accepted;
}

void LightRig::advance(std::int64_t nowNs) {
    lastAdvanceNs_ = std::max(lastAdvanceNs_, nowNs);
    current_ = lightAt(lastAdvanceNs_);
}

std::array<float, 3> LightRig::position() const {
    const std::array<double, 3> p = sphere_.toPosition(current_);
    return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

SharedLight LightRig::shared() const {
    // Every field named: a field added to SharedLight and not given here fails the build
    // (-Wmissing-field-initializers), so the bus never carries a default by mistake.
    return SharedLight{.from = from_,
                       .target = target_,
                       .moveStartNs = moveStartNs_,
                       .driftAtNs = driftAtNs_,
                       .preset = preset_,
                       .revisionNs = revisionNs_,
                       .steeredBy = steeredBy_};
}

void LightRig::rebase(const LightSphere& sphere, int presetCount) {
    sphere_ = sphere;
    limits_ = resolved(config_.limits, sphere_);
    presetCount_ = std::max(presetCount, 1);
    preset_ = std::min(preset_, presetCount_ - 1);
    initial_ = clamped(initialOf(config_, sphere_));
    from_ = clamped(from_);
    target_ = clamped(target_);
    current_ = clamped(current_);
}

}  // namespace vpe::firmware
