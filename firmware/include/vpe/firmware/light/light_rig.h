// SPDX-License-Identifier: MIT
// LightRig: the virtual light's state. Inputs' events move a target on the LightSphere, clamped
// to the board's limits; the light follows the target with exponential smoothing. The last
// active input wins (every event makes its source the active one); after the idle quiet time
// without events, or once the active source releases, the IdleDrift takes over, and any input
// takes it back from wherever the drift had brought the light.
//
// The light is a function of time, not of how often it is looked at: a move starts at a time
// from the light at that time and approaches its target as 1 − exp(−t/τ), the drift starts at a
// fixed time (the last move's + quiet_s, or the release's) and its path's phase is the clock's.
// So nodes that share a clock and the state (SharedLight, firmware/bus/) draw the same light at
// the same time, whatever their frame rates.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/input/shared_light.h"
#include "vpe/firmware/light/idle_drift.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware {

class LightRig {
public:
    // presetCount: the bundle's weight presets (SelectPreset wraps or is refused against it).
    // nowNs: the rig's clock now (CLOCK_MONOTONIC, or CLOCK_REALTIME for a shared light).
    LightRig(const LightConfig& light, const IdleConfig& idle, const LightSphere& sphere,
             int presetCount, std::int64_t nowNs);

    // Applies one event, its timestamp on the rig's clock; false when it was refused (a preset
    // index out of range). A steering event starts a move at its time, or at the last advance
    // when that is later (the frame already shown), from the light there. A FollowLight older
    // than the rig's own state changes nothing (counted by staleStates()).
    bool apply(const InputEvent& event);
    // The light at `nowNs` (non-decreasing; a frame's presentation time).
    void advance(std::int64_t nowNs);

    // The light the next frame shows, and where it is heading (the drift's own position while
    // drifting).
    const SphericalPosition& current() const { return current_; }
    SphericalPosition target() const { return idle() ? current_ : target_; }
    std::array<float, 3> position() const;
    int preset() const { return preset_; }
    // The source steering now: kIdle while drifting (or before any input).
    InputSource activeSource() const { return idle() ? InputSource::kIdle : steeredBy_; }
    bool idle() const { return driftingAt(lastAdvanceNs_); }
    // Timestamp of the newest event applied (0: none).
    std::int64_t lastEventNs() const { return lastEventNs_; }

    // The state another node needs to draw the same light (firmware/bus/).
    SharedLight shared() const;
    // When the state last changed (a move, a preset, a release, another node's state).
    std::int64_t revisionNs() const { return revisionNs_; }
    // Other nodes' states ignored for being no newer than this rig's own.
    std::uint64_t staleStates() const { return staleStates_; }

    // With a shared light (firmware/bus/), a move or a release starts this long after its event
    // (a frame): by the time it shows, every node has heard of it, so all of them show it from
    // the same frame on; a node that rendered a frame for a later moment before the state
    // arrived would otherwise show the old path there. 0 (alone): at once.
    void setMoveLead(std::int64_t leadNs) { moveLeadNs_ = leadNs; }

    // A new bundle (mesh, presets) while playing: the angles stay, limits are re-derived.
    void rebase(const LightSphere& sphere, int presetCount);

    const LightLimits& limits() const { return limits_; }

private:
    SphericalPosition clamped(SphericalPosition p) const;
    bool driftingAt(std::int64_t nowNs) const { return driftAtNs_ && nowNs >= *driftAtNs_; }
    // The move alone (no drift) at `nowNs`, and the light (the drift from its start on).
    SphericalPosition movedAt(std::int64_t nowNs) const;
    SphericalPosition lightAt(std::int64_t nowNs) const;
    // A steering event at `eventNs`: a new move toward `aim(base)`, where base is the target
    // (or the light, while drifting).
    template <typename Aim>
    void steer(InputSource source, std::int64_t eventNs, Aim aim);
    void follow(const SharedLight& state);
    void touched(std::int64_t eventNs);

    LightConfig config_;
    IdleDrift drift_;
    IdleConfig idleConfig_;
    LightSphere sphere_;
    LightLimits limits_;  // with the distance range resolved
    SphericalPosition initial_;
    // The move: from from_ at moveStartNs_ toward target_.
    SphericalPosition from_, target_;
    std::int64_t moveStartNs_;
    std::optional<std::int64_t> driftAtNs_;
    std::int64_t revisionNs_ = 0;
    SphericalPosition current_;  // at lastAdvanceNs_
    int presetCount_;
    int preset_ = 0;
    InputSource steeredBy_ = InputSource::kIdle;
    std::int64_t lastEventNs_ = 0;
    std::int64_t lastAdvanceNs_;
    std::int64_t moveLeadNs_ = 0;
    std::uint64_t staleStates_ = 0;
};

}  // namespace vpe::firmware
