// SPDX-License-Identifier: MIT
// The [camera] section, read strictly with the shared board-file helpers.
#include "vpe/firmware/tracking/camera_config.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

#include "board/toml_fields.h"

namespace vpe::firmware {

namespace {

using namespace toml_fields;

constexpr const char* kSection = "camera";
constexpr int kMaxSide = 4096;

double pointValue(const toml::array& point, std::size_t index, const std::string& source,
                  const std::string& key) {
    const toml::node& node = point[index];
    if (!node.is_number()) {
        fail(source, key,
             std::string("expected [u, v, azimuth_deg, elevation_deg] numbers, got ") +
                 typeName(node) + " at position " + std::to_string(index));
    }
    const double value = *node.value<double>();
    if (!std::isfinite(value)) {
        fail(source, key, "expected finite numbers");
    }
    return value;
}

std::vector<CalibrationPoint> parseCalibration(const toml::table& camera, const std::string& source,
                                               int width, int height) {
    std::vector<CalibrationPoint> points;
    const toml::node* node = camera.get("calibration");
    if (node == nullptr) {
        return points;
    }
    const std::string name = qualified(kSection, "calibration");
    const toml::array* array = node->as_array();
    if (array == nullptr) {
        fail(source, name,
             std::string("expected an array of [u, v, azimuth_deg, elevation_deg] points, got ") +
                 typeName(*node));
    }
    for (std::size_t i = 0; i < array->size(); ++i) {
        const std::string key = name + "[" + std::to_string(i) + "]";
        const toml::node& element = (*array)[i];
        const toml::array* point = element.as_array();
        if (point == nullptr || point->size() != 4) {
            fail(source, key,
                 std::string("expected [u, v, azimuth_deg, elevation_deg], got ") +
                     (point == nullptr ? typeName(element)
                                       : "an array of " + std::to_string(point->size())));
        }
        CalibrationPoint p;
        p.u = pointValue(*point, 0, source, key);
        p.v = pointValue(*point, 1, source, key);
        p.azimuthDeg = pointValue(*point, 2, source, key);
        p.elevationDeg = pointValue(*point, 3, source, key);
        if (p.u < 0.0 || p.u > width - 1 || p.v < 0.0 || p.v > height - 1) {
            fail(source, key,
                 "image position (" + numberText(p.u) + ", " + numberText(p.v) +
                     ") is outside the " + std::to_string(width) + "x" + std::to_string(height) +
                     " image (camera.size)");
        }
        if (std::abs(p.azimuthDeg) > 360.0) {
            fail(source, key, "azimuth " + numberText(p.azimuthDeg) + " is outside [-360, 360]");
        }
        if (std::abs(p.elevationDeg) > 90.0) {
            fail(source, key, "elevation " + numberText(p.elevationDeg) + " is outside [-90, 90]");
        }
        points.push_back(p);
    }
    return points;
}

}  // namespace

CameraConfig parseCameraConfig(const toml::table& camera, const std::string& source) {
    checkKeys(
        camera, source, kSection,
        {"enabled", "id", "size", "exposure_us", "analogue_gain", "threshold", "relative_threshold",
         "min_area", "max_area", "hold_s", "filter", "calibration", "lamp_distance_m"});
    CameraConfig config;
    config.enabled = optionalBool(camera, source, kSection, "enabled").value_or(false);
    if (auto id = optionalString(camera, source, kSection, "id")) {
        if (id->empty()) {
            fail(source, "camera.id", "is empty (\"auto\" or a libcamera camera id)");
        }
        config.id = *id;
    }
    LampTrackerSettings& tracking = config.tracking;
    if (auto size = optionalString(camera, source, kSection, "size")) {
        const std::optional<DisplayMode> parsed = parseDisplayMode(*size);
        if (!parsed || parsed->refresh != 0 || parsed->width > kMaxSide ||
            parsed->height > kMaxSide) {
            fail(source, "camera.size",
                 "expected \"WxH\" (at most 4096x4096), got \"" + *size + "\"");
        }
        tracking.width = parsed->width;
        tracking.height = parsed->height;
    }
    config.exposureUs =
        integerIn(camera, source, kSection, "exposure_us", 1, 1'000'000, config.exposureUs);
    config.analogueGain =
        numberIn(camera, source, kSection, "analogue_gain", 1.0, false, 64.0, config.analogueGain);

    BlobTrackerConfig& blob = tracking.blob;
    blob.threshold = integerIn(camera, source, kSection, "threshold", 1, 255, blob.threshold);
    if (auto relative = optionalNumber(camera, source, kSection, "relative_threshold")) {
        if (!(*relative >= 0.0 && *relative < 1.0)) {
            fail(source, "camera.relative_threshold",
                 "expected a number in [0, 1), got " + numberText(*relative));
        }
        blob.relativeThreshold = *relative;
    }
    const long long pixels = static_cast<long long>(tracking.width) * tracking.height;
    blob.minArea = integerIn(camera, source, kSection, "min_area", 1, pixels, blob.minArea);
    blob.maxArea = integerIn(camera, source, kSection, "max_area", 1, pixels,
                             static_cast<int>(std::min<long long>(blob.maxArea, pixels)));
    if (blob.minArea > blob.maxArea) {
        fail(source, "camera.min_area",
             std::to_string(blob.minArea) + " is above max_area " + std::to_string(blob.maxArea));
    }
    tracking.holdSeconds =
        numberIn(camera, source, kSection, "hold_s", 0.0, true, 3600.0, tracking.holdSeconds);

    if (const toml::table* filter = optionalTable(camera, source, kSection, "filter")) {
        const std::string section = "camera.filter";
        checkKeys(*filter, source, section, {"min_cutoff", "beta", "d_cutoff"});
        OneEuroParameters& parameters = tracking.filter;
        parameters.minCutoffHz = numberIn(*filter, source, section, "min_cutoff", 0.0, true, 1000.0,
                                          parameters.minCutoffHz);
        parameters.beta =
            numberIn(*filter, source, section, "beta", 0.0, false, 1000.0, parameters.beta);
        parameters.derivativeCutoffHz = numberIn(*filter, source, section, "d_cutoff", 0.0, true,
                                                 1000.0, parameters.derivativeCutoffHz);
    }

    if (camera.contains("lamp_distance_m")) {
        config.lampDistanceM =
            numberIn(camera, source, kSection, "lamp_distance_m", 0.0, true, 1000.0, 1.0);
    }
    config.calibration = parseCalibration(camera, source, tracking.width, tracking.height);
    if (!config.calibration.empty()) {
        try {
            LampCalibration::fit(config.calibration);
        } catch (const CalibrationError& error) {
            fail(source, "camera.calibration", error.what());
        }
    }
    return config;
}

LampDirectionMap lampDirectionMapOf(const CameraConfig& config,
                                    const std::optional<proto::PinholeCamera>& bundleCamera,
                                    const LightSphere& sphere, const LightConfig& light,
                                    const std::string& source) {
    if (!config.calibration.empty()) {
        try {
            return LampCalibration::fit(config.calibration);
        } catch (const CalibrationError& error) {
            fail(source, "camera.calibration", error.what());
        }
    }
    if (!bundleCamera) {
        fail(source, "camera.calibration",
             "absent, and the bundle carries no camera (bake it from a scan or a calibration "
             "with cam_K)");
    }
    const double radius =
        config.lampDistanceM.value_or(light.initialDistanceM.value_or(2.0 * sphere.objectRadius()));
    try {
        return CameraLampModel(*bundleCamera, config.tracking.width, config.tracking.height, sphere,
                               radius);
    } catch (const CalibrationError& error) {
        fail(source, "camera.size", error.what());
    }
}

std::string describeLampDirectionMap(const LampDirectionMap& map) {
    if (const auto* table = std::get_if<LampCalibration>(&map)) {
        return std::string("the table (") +
               (table->model() == LampCalibration::Model::kAffine ? "affine" : "quadratic") +
               ", rms residual " + numberText(table->rmsResidualDeg()) + "°)";
    }
    const auto& model = std::get<CameraLampModel>(map);
    const proto::PinholeCamera& calibrated = model.calibratedCamera();
    const proto::PinholeCamera& stream = model.streamCamera();
    return "the bundle's camera (" + std::to_string(calibrated.width) + "x" +
           std::to_string(calibrated.height) + " scaled to " + std::to_string(stream.width) + "x" +
           std::to_string(stream.height) + "; lamp sphere " + numberText(model.radiusM()) +
           " m, the camera " + (model.cameraInsideSphere() ? "inside" : "outside") + " it)";
}

}  // namespace vpe::firmware
