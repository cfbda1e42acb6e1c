// SPDX-License-Identifier: MIT
// The lamp-direction survey: true camera → synthetic frames → LampTracker with the model.
#include "lamp_direction_survey.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

namespace vpe::firmware::testing {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr std::int64_t kFrameNs = 40'000'000;

proto::Vec3d unitDirection(double azimuthDeg, double elevationDeg) {
    const double az = azimuthDeg * kDegree, el = elevationDeg * kDegree;
    return {std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az)};
}

double angleDeg(const proto::Vec3d& a, const proto::Vec3d& b) {
    // atan2 of |a × b| and a·b: accurate at small angles, where acos is not.
    const proto::Vec3d c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return std::atan2(std::sqrt(proto::dot(c, c)), proto::dot(a, b)) / kDegree;
}

// Whether the camera's pixel ray points back at the point it was projected from. OpenCV's
// distortion polynomial folds over far outside a wide lens's field, and points there "project"
// into the image though no lens shows them: no model could place them.
bool oneToOne(const proto::PinholeCamera& camera, const proto::Vec2d& pixel,
              const proto::Vec3d& unitRay) {
    const proto::Vec3d back = proto::normalized(proto::pixelRayDirection(camera, pixel));
    return angleDeg(back, unitRay) < 1e-3;
}

std::vector<double> mappedErrors(const std::vector<LampSurveyPosition>& positions) {
    std::vector<double> errors;
    for (const LampSurveyPosition& p : positions) {
        if (p.errorDeg) {
            errors.push_back(*p.errorDeg);
        }
    }
    std::sort(errors.begin(), errors.end());
    return errors;
}

}  // namespace

std::size_t LampSurvey::unmapped() const {
    return static_cast<std::size_t>(
        std::count_if(positions.begin(), positions.end(),
                      [](const LampSurveyPosition& p) { return !p.errorDeg.has_value(); }));
}

double LampSurvey::medianErrorDeg() const {
    const std::vector<double> errors = mappedErrors(positions);
    if (errors.empty()) {
        return 0.0;
    }
    const std::size_t half = errors.size() / 2;
    return errors.size() % 2 == 1 ? errors[half] : 0.5 * (errors[half - 1] + errors[half]);
}

double LampSurvey::maxErrorDeg() const {
    const std::vector<double> errors = mappedErrors(positions);
    return errors.empty() ? 0.0 : errors.back();
}

std::vector<double> steps(double first, double last, double step) {
    std::vector<double> values;
    for (int i = 0; first + i * step <= last + 1e-9; ++i) {
        values.push_back(first + i * step);
    }
    return values;
}

LampSurvey surveyLampDirections(const proto::PinholeCamera& trueCamera,
                                const CameraLampModel& model, const LightSphere& sphere,
                                double radiusM, const LampSurveySettings& settings) {
    LampSurvey survey;
    const proto::Vec3d eye = trueCamera.center();
    const std::array<double, 3>& c = sphere.centre();
    const proto::Vec3d centre{c[0], c[1], c[2]};
    const proto::Vec3d fromCentre{eye.x - centre.x, eye.y - centre.y, eye.z - centre.z};
    const bool inside = proto::dot(fromCentre, fromCentre) <= radiusM * radiusM;
    const double sx = static_cast<double>(settings.streamWidth) / trueCamera.width;
    const double sy = static_cast<double>(settings.streamHeight) / trueCamera.height;
    const double margin = 3.0 * settings.spotRadiusPx;
    LampTrackerSettings tracking;
    tracking.width = settings.streamWidth;
    tracking.height = settings.streamHeight;
    std::uint32_t seed = settings.seed;
    for (const double elevation : settings.elevationsDeg) {
        for (const double azimuth : settings.azimuthsDeg) {
            const std::array<double, 3> p = sphere.toPosition({azimuth, elevation, radiusM});
            const proto::Vec3d lamp{p[0], p[1], p[2]};
            const std::optional<proto::Vec2d> pixel = proto::projectToPixel(trueCamera, lamp);
            const proto::Vec3d ray =
                proto::normalized(proto::Vec3d{lamp.x - eye.x, lamp.y - eye.y, lamp.z - eye.z});
            const proto::Vec3d normal = proto::normalized(
                proto::Vec3d{lamp.x - centre.x, lamp.y - centre.y, lamp.z - centre.z});
            const double facing = proto::dot(ray, normal);  // < 0: the near side, seen from out
            if (!pixel || (!inside && facing >= 0) || !oneToOne(trueCamera, *pixel, ray)) {
                ++survey.skipped;
                continue;
            }
            // Pixel centres at integers: the stream's pixel is the calibrated one scaled.
            const double u = (pixel->x + 0.5) * sx - 0.5, v = (pixel->y + 0.5) * sy - 0.5;
            if (u < margin || v < margin || u > settings.streamWidth - 1 - margin ||
                v > settings.streamHeight - 1 - margin) {
                ++survey.skipped;
                continue;
            }
            LampSurveyPosition position;
            position.azimuthDeg = azimuth;
            position.elevationDeg = elevation;
            position.u = u;
            position.v = v;
            position.incidenceDeg = std::acos(std::min(1.0, std::abs(facing))) / kDegree;
            LampTracker tracker(tracking, model);
            std::vector<InputEvent> events;
            for (int frame = 0; frame < settings.framesPerPosition; ++frame) {
                SyntheticLampFrame scene;
                scene.width = settings.streamWidth;
                scene.height = settings.streamHeight;
                scene.noiseSigma = settings.noiseSigma;
                scene.seed = seed++;
                scene.lamp = SyntheticSpot{u, v, settings.spotRadiusPx, settings.spotPeak};
                events.clear();
                tracker.onFrame(scene.render().view(), frame * kFrameNs, events);
            }
            if (!events.empty()) {
                if (const auto* aim = std::get_if<AimLight>(&events.back().action);
                    aim != nullptr && aim->azimuthDeg && aim->elevationDeg) {
                    position.errorDeg =
                        angleDeg(unitDirection(azimuth, elevation),
                                 unitDirection(*aim->azimuthDeg, *aim->elevationDeg));
                }
            }
            survey.positions.push_back(position);
        }
    }
    return survey;
}

}  // namespace vpe::firmware::testing
