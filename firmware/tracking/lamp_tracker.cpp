// SPDX-License-Identifier: MIT
// LampTracker: blob → smoothing → direction map, and the hold-then-release of a lost lamp.
#include "vpe/firmware/tracking/lamp_tracker.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace vpe::firmware {

namespace {

double secondsOf(std::int64_t ns) {
    return static_cast<double>(ns) * 1e-9;
}

// Pixel centres sit at integers, so scaling maps the image's edges (−½ and size − ½) onto each
// other rather than the first pixel's centre.
double rescale(double position, int from, int to) {
    if (from == to) {
        return position;
    }
    return (position + 0.5) * static_cast<double>(to) / static_cast<double>(from) - 0.5;
}

}  // namespace

LampTracker::LampTracker(const LampTrackerSettings& settings, LampDirectionMap map)
    : settings_(settings),
      map_(std::move(map)),
      blobs_(settings.blob),
      filterU_(settings.filter),
      filterV_(settings.filter) {
    if (settings.width <= 0 || settings.height <= 0) {
        throw std::invalid_argument("lamp tracker: image size must be positive, got " +
                                    std::to_string(settings.width) + "x" +
                                    std::to_string(settings.height));
    }
    if (!(std::isfinite(settings.holdSeconds) && settings.holdSeconds > 0.0 &&
          settings.holdSeconds <= 3600.0)) {
        throw std::invalid_argument("lamp tracker: hold time must be in (0, 3600] s, got " +
                                    std::to_string(settings.holdSeconds));
    }
    holdNs_ = std::llround(settings.holdSeconds * 1e9);
}

void LampTracker::onFrame(const LuminanceView& frame, std::int64_t timestampNs,
                          std::vector<InputEvent>& events) {
    lastBlob_ = blobs_.find(frame);
    if (!lastBlob_) {
        releaseIfHoldExpired(timestampNs, events);
        return;
    }
    if (!steering_) {
        // Found again after a release (or for the first time): start smoothing afresh here.
        filterU_.reset();
        filterV_.reset();
    }
    const double seconds = secondsOf(timestampNs);
    const double u = filterU_.filter(rescale(lastBlob_->x, frame.width, settings_.width), seconds);
    const double v =
        filterV_.filter(rescale(lastBlob_->y, frame.height, settings_.height), seconds);
    const std::optional<LightDirection> direction = std::visit(
        [u, v](const auto& map) { return std::optional<LightDirection>(map.direction(u, v)); },
        map_);
    if (!direction) {
        // Seen, but off the lamp's sphere (a reflection, or the lamp held far from where the
        // model expects it): this frame does not show where the lamp is.
        ++unmappedFrames_;
        releaseIfHoldExpired(timestampNs, events);
        return;
    }
    events.push_back(InputEvent{InputSource::kCamera, timestampNs,
                                AimLight{direction->azimuthDeg, direction->elevationDeg, {}}});
    steering_ = true;
    lastSeenNs_ = timestampNs;
}

std::map<std::string, std::uint64_t> LampTracker::refusals() const {
    if (unmappedFrames_ == 0) {
        return {};
    }
    return {{kLampRayMissesSphere, unmappedFrames_}};
}

void LampTracker::tick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    releaseIfHoldExpired(nowNs, events);
}

void LampTracker::releaseIfHoldExpired(std::int64_t nowNs, std::vector<InputEvent>& events) {
    if (!steering_ || nowNs - lastSeenNs_ < holdNs_) {
        return;
    }
    // Stamped when the hold ran out, not when it was noticed: the same for every caller.
    events.push_back(InputEvent{InputSource::kCamera, lastSeenNs_ + holdNs_, ReleaseLight{}});
    steering_ = false;
}

}  // namespace vpe::firmware
