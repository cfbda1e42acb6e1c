// SPDX-License-Identifier: MIT
#include "vpe/firmware/board/light_config.h"

#include "board/toml_fields.h"

namespace vpe::firmware {

namespace {

using namespace toml_fields;

void requireWithin(const std::pair<double, double>& range, double low, double high,
                   const std::string& source, const std::string& key) {
    if (range.first < low || range.second > high) {
        fail(source, key,
             "must lie within [" + std::to_string(static_cast<int>(low)) + ", " +
                 std::to_string(static_cast<int>(high)) + "]");
    }
}

void requirePositive(double value, const std::string& source, const std::string& key,
                     bool allowZero) {
    if (value < 0 || (!allowZero && value == 0)) {
        fail(source, key, allowZero ? "must not be negative" : "must be positive");
    }
}

}  // namespace

LightConfig parseLightConfig(const toml::table* light, const std::string& source) {
    LightConfig config;
    if (light == nullptr) {
        return config;
    }
    const std::string s = "light";
    checkKeys(*light, source, s,
              {"azimuth", "elevation", "distance", "initial_azimuth", "initial_elevation",
               "initial_distance", "smoothing_s", "intensity", "inverse_square"});
    if (auto range = optionalRange(*light, source, s, "azimuth")) {
        requireWithin(*range, -180.0, 180.0, source, "light.azimuth");
        config.limits.azimuthDeg = *range;
    }
    if (auto range = optionalRange(*light, source, s, "elevation")) {
        requireWithin(*range, -90.0, 90.0, source, "light.elevation");
        config.limits.elevationDeg = *range;
    }
    if (auto range = optionalRange(*light, source, s, "distance")) {
        if (range->first <= 0) {
            fail(source, "light.distance", "must be positive (metres from the object's centre)");
        }
        config.limits.distanceM = *range;
    }
    config.initialAzimuthDeg =
        optionalNumber(*light, source, s, "initial_azimuth").value_or(config.initialAzimuthDeg);
    config.initialElevationDeg =
        optionalNumber(*light, source, s, "initial_elevation").value_or(config.initialElevationDeg);
    config.initialDistanceM = optionalNumber(*light, source, s, "initial_distance");
    if (config.initialDistanceM) {
        requirePositive(*config.initialDistanceM, source, "light.initial_distance", false);
    }
    config.smoothingSeconds =
        optionalNumber(*light, source, s, "smoothing_s").value_or(config.smoothingSeconds);
    requirePositive(config.smoothingSeconds, source, "light.smoothing_s", true);
    config.intensity = optionalNumber(*light, source, s, "intensity").value_or(config.intensity);
    requirePositive(config.intensity, source, "light.intensity", true);
    config.inverseSquare =
        optionalBool(*light, source, s, "inverse_square").value_or(config.inverseSquare);
    return config;
}

IdleConfig parseIdleConfig(const toml::table* idle, const std::string& source) {
    IdleConfig config;
    if (idle == nullptr) {
        return config;
    }
    const std::string s = "idle";
    checkKeys(*idle, source, s,
              {"enabled", "quiet_s", "period_s", "azimuth", "elevation", "handover_s"});
    config.enabled = optionalBool(*idle, source, s, "enabled").value_or(config.enabled);
    config.quietSeconds = optionalNumber(*idle, source, s, "quiet_s").value_or(config.quietSeconds);
    requirePositive(config.quietSeconds, source, "idle.quiet_s", true);
    config.periodSeconds =
        optionalNumber(*idle, source, s, "period_s").value_or(config.periodSeconds);
    requirePositive(config.periodSeconds, source, "idle.period_s", false);
    if (auto range = optionalRange(*idle, source, s, "azimuth")) {
        requireWithin(*range, -180.0, 180.0, source, "idle.azimuth");
        config.azimuthDeg = *range;
    }
    if (auto range = optionalRange(*idle, source, s, "elevation")) {
        requireWithin(*range, -90.0, 90.0, source, "idle.elevation");
        config.elevationDeg = *range;
    }
    config.handoverSeconds =
        optionalNumber(*idle, source, s, "handover_s").value_or(config.handoverSeconds);
    requirePositive(config.handoverSeconds, source, "idle.handover_s", true);
    return config;
}

}  // namespace vpe::firmware
