// SPDX-License-Identifier: MIT
// LightRig: the virtual light's state. Inputs' events move a target on the LightSphere, clamped
// to the board's limits; the light follows the target with exponential smoothing. The last
// active input wins (every event makes its source the active one); after the idle quiet time
// without events, or once the active source releases, the IdleDrift takes over, and any input
// takes it back from wherever the drift had brought the light.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/light/idle_drift.h"
#include "vpe/firmware/light/light_config.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware {

class LightRig {
public:
    // presetCount: the bundle's weight presets (SelectPreset wraps or is refused against it).
    LightRig(const LightConfig& light, const IdleConfig& idle, const LightSphere& sphere,
             int presetCount, std::int64_t nowNs);

    // Applies one event; false when it was refused (a preset index out of range). Events must
    // come in timestamp order per source; the rig does not reorder.
    bool apply(const InputEvent& event);
    // Advances the smoothing and the idle drift to `nowNs` (monotonic, non-decreasing).
    void advance(std::int64_t nowNs);

    // The smoothed light the next frame shows, and where it is heading.
    const SphericalPosition& current() const { return current_; }
    const SphericalPosition& target() const { return target_; }
    std::array<float, 3> position() const;
    int preset() const { return preset_; }
    // The source steering now: kIdle while drifting (or before any input).
    InputSource activeSource() const { return active_; }
    bool idle() const { return idleSince_.has_value(); }
    // Timestamp of the newest event applied (0: none): the frame loop's latency clock.
    std::int64_t lastEventNs() const { return lastEventNs_; }

    // A new bundle (mesh, presets) while playing: the angles stay, limits are re-derived.
    void rebase(const LightSphere& sphere, int presetCount);

    const LightLimits& limits() const { return limits_; }

private:
    SphericalPosition clamped(SphericalPosition p) const;
    void leaveIdle();

    LightConfig config_;
    IdleDrift drift_;
    IdleConfig idleConfig_;
    LightSphere sphere_;
    LightLimits limits_;  // with the distance range resolved
    SphericalPosition initial_, target_, current_;
    int presetCount_;
    int preset_ = 0;
    InputSource active_ = InputSource::kIdle;
    std::int64_t lastInputNs_;  // any input's newest event, or construction/release time
    std::int64_t lastEventNs_ = 0;
    std::int64_t lastAdvanceNs_;
    std::optional<std::int64_t> idleSince_;
    SphericalPosition idleFrom_;
};

}  // namespace vpe::firmware
