// SPDX-License-Identifier: MIT
#include "vpe/firmware/light/light_rig.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace vpe::firmware {

namespace {

constexpr double kNsPerSecond = 1e9;

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
      presetCount_(std::max(presetCount, 1)),
      lastInputNs_(nowNs),
      lastAdvanceNs_(nowNs) {
    initial_ = target_ = current_ = clamped(initialOf(config_, sphere_));
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

void LightRig::leaveIdle() {
    if (idleSince_) {
        // Steering resumes from where the drift brought the light: no jump back.
        target_ = current_;
        idleSince_.reset();
    }
}

bool LightRig::apply(const InputEvent& event) {
    bool accepted = true;
    bool steers = true;  // does the event move the light (and so make its source active)?
    std::visit(
        [&](const auto& action) {
            using Action = std::decay_t<decltype(action)>;
            if constexpr (std::is_same_v<Action, TurnLight>) {
                leaveIdle();
                target_.azimuthDeg += action.azimuthDeg;
                target_.elevationDeg += action.elevationDeg;
                target_.distanceM += action.distanceM;
            } else if constexpr (std::is_same_v<Action, AimLight>) {
                leaveIdle();
                target_.azimuthDeg = action.azimuthDeg.value_or(target_.azimuthDeg);
                target_.elevationDeg = action.elevationDeg.value_or(target_.elevationDeg);
                target_.distanceM = action.distanceM.value_or(target_.distanceM);
            } else if constexpr (std::is_same_v<Action, PlaceLight>) {
                leaveIdle();
                target_ = sphere_.fromPosition(action.position);
            } else if constexpr (std::is_same_v<Action, ResetLight>) {
                leaveIdle();
                target_ = initial_;
            } else if constexpr (std::is_same_v<Action, SelectPreset>) {
                // Choosing a material is not steering: the light keeps what it was doing.
                steers = false;
                if (action.relative) {
                    preset_ =
                        ((preset_ + action.value) % presetCount_ + presetCount_) % presetCount_;
                } else if (action.value >= 0 && action.value < presetCount_) {
                    preset_ = action.value;
                } else {
                    accepted = false;
                }
            } else if constexpr (std::is_same_v<Action, ReleaseLight>) {
                steers = false;
                // Only the steering source can let go; the drift starts at once, since the
                // source already waited (a lost lamp holds for its hold time first).
                if (event.source == active_ && idleConfig_.enabled && !idleSince_) {
                    idleSince_ = event.timestampNs;
                    idleFrom_ = current_;
                    active_ = InputSource::kIdle;
                }
            }
        },
        event.action);
    if (steers) {
        target_ = clamped(target_);
        active_ = event.source;
        lastInputNs_ = std::max(lastInputNs_, event.timestampNs);
    }
    if (accepted) {
        lastEventNs_ = std::max(lastEventNs_, event.timestampNs);
    }
    return accepted;
}

void LightRig::advance(std::int64_t nowNs) {
    const double dt =
        static_cast<double>(std::max<std::int64_t>(nowNs - lastAdvanceNs_, 0)) / kNsPerSecond;
    lastAdvanceNs_ = std::max(lastAdvanceNs_, nowNs);
    if (!idleSince_ && idleConfig_.enabled &&
        static_cast<double>(nowNs - lastInputNs_) >= idleConfig_.quietSeconds * kNsPerSecond) {
        idleSince_ = nowNs;
        idleFrom_ = current_;
        active_ = InputSource::kIdle;
    }
    if (idleSince_) {
        const double seconds =
            static_cast<double>(std::max<std::int64_t>(nowNs - *idleSince_, 0)) / kNsPerSecond;
        target_ = current_ = clamped(drift_.position(idleFrom_, seconds));
        return;
    }
    const double follow =
        config_.smoothingSeconds <= 0 ? 1.0 : 1.0 - std::exp(-dt / config_.smoothingSeconds);
    double dAz = target_.azimuthDeg - current_.azimuthDeg;
    if (wraps(limits_)) {
        dAz = std::remainder(dAz, 360.0);
    }
    current_.azimuthDeg += follow * dAz;
    current_.elevationDeg += follow * (target_.elevationDeg - current_.elevationDeg);
    current_.distanceM += follow * (target_.distanceM - current_.distanceM);
    current_ = clamped(current_);
}

std::array<float, 3> LightRig::position() const {
    const std::array<double, 3> p = sphere_.toPosition(current_);
    return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

void LightRig::rebase(const LightSphere& sphere, int presetCount) {
    sphere_ = sphere;
    limits_ = resolved(config_.limits, sphere_);
    presetCount_ = std::max(presetCount, 1);
    preset_ = std::min(preset_, presetCount_ - 1);
    initial_ = clamped(initialOf(config_, sphere_));
    target_ = clamped(target_);
    current_ = clamped(current_);
    if (idleSince_) {
        idleFrom_ = clamped(idleFrom_);
    }
}

}  // namespace vpe::firmware
