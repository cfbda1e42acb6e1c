// SPDX-License-Identifier: MIT
// vpe_lamp_direction --bundle scene.vpeb --true-camera true.yml [--radius M] [--json]
//
// What the bundle's calibrated camera costs the tracked lamp (firmware/tracking/README.md, "The
// camera model"): the lamp is put on its sphere (radius M, default twice the object's bounding
// radius, as a board without lamp_distance_m or [light] initial_distance has it) at azimuth
// −180…165 every 15° (180 is −180) and elevation −10…80 every 10°; those the TRUE camera sees —
// in front of it, inside its image, on the sphere's side facing it — are projected through it
// into the default 320 × 240 tracking stream, drawn as noisy synthetic spots, tracked by the
// real LampTracker with the bundle's camera model, and the direction it reports is compared with
// where the lamp was. true.yml is an OpenCV FileStorage file with cam_K, cam_kc, cam_width,
// cam_height and the true camera's pose R, T (object frame → camera; length_unit, else metres),
// as scene::writeCameraCalibration writes it. Prints the median and largest error in degrees;
// with --json, the last line is {"lamp_error_deg_max", "lamp_error_deg_median", "positions",
// "unmapped"}: unmapped positions (the bundle's model sees the lamp off its sphere) are counted
// apart and left out of both figures. Bad input: one line, exit status 2.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/firmware/light/light_sphere.h"
#include "vpe/firmware/tracking/camera_lamp_model.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/scene/projector_calibration.h"

#include "lamp_direction_survey.h"

namespace {

namespace fw = vpe::firmware;

constexpr const char* kUsage =
    "usage: vpe_lamp_direction --bundle scene.vpeb --true-camera true.yml [--radius M] [--json]\n";

struct Arguments {
    std::filesystem::path bundle, trueCamera;
    std::optional<double> radius;
    bool json = false;
};

std::optional<Arguments> parse(const std::vector<std::string>& args) {
    Arguments parsed;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const bool hasValue = i + 1 < args.size();
        if (args[i] == "--bundle" && hasValue) {
            parsed.bundle = args[++i];
        } else if (args[i] == "--true-camera" && hasValue) {
            parsed.trueCamera = args[++i];
        } else if (args[i] == "--radius" && hasValue) {
            const std::string& text = args[++i];
            std::size_t end = 0;
            double value = 0;
            try {
                value = std::stod(text, &end);
            } catch (const std::exception&) {
                end = 0;
            }
            if (end != text.size() || !(value > 0 && value <= 1000)) {
                throw vpe::common::InputError("--radius: expected metres in (0, 1000], got '" +
                                              text + "'");
            }
            parsed.radius = value;
        } else if (args[i] == "--json") {
            parsed.json = true;
        } else {
            return std::nullopt;
        }
    }
    if (parsed.bundle.empty() || parsed.trueCamera.empty()) {
        return std::nullopt;
    }
    return parsed;
}

int run(const Arguments& args) {
    const vpe::proto::BundleFile bundle = [&] {
        try {
            return vpe::proto::BundleFile::open(args.bundle);
        } catch (const vpe::proto::BundleError& error) {
            throw vpe::common::InputError(error.what());
        }
    }();
    if (!bundle->camera()) {
        throw vpe::common::InputError(args.bundle,
                                      "the bundle carries no camera (format 1.3: bake it from a "
                                      "calibration with cam_K)");
    }
    const std::optional<vpe::proto::PinholeCamera> trueCamera =
        vpe::scene::readCameraCalibration(args.trueCamera, vpe::scene::CameraPose::kFromFile);
    if (!trueCamera) {
        throw vpe::common::InputError(
            args.trueCamera,
            "cam_K: missing (the true camera needs cam_K, cam_kc, cam_width, "
            "cam_height, R and T)");
    }
    const fw::LightSphere sphere(bundle->mesh().positions, bundle->settings().viewerPosition);
    const double radius = args.radius.value_or(2.0 * sphere.objectRadius());
    fw::testing::LampSurveySettings settings;
    settings.azimuthsDeg = fw::testing::steps(-180.0, 165.0, 15.0);
    settings.elevationsDeg = fw::testing::steps(-10.0, 80.0, 10.0);
    const std::optional<fw::CameraLampModel> model = [&]() -> std::optional<fw::CameraLampModel> {
        try {
            return fw::CameraLampModel(vpe::proto::cameraOf(*bundle->camera()),
                                       settings.streamWidth, settings.streamHeight, sphere, radius);
        } catch (const fw::CalibrationError& error) {
            throw vpe::common::InputError(args.bundle, std::string("camera: ") + error.what());
        }
    }();
    // The true camera at another shape than the stream would be a crop: no lamp could be drawn
    // where it is.
    try {
        fw::CameraLampModel(*trueCamera, settings.streamWidth, settings.streamHeight, sphere,
                            radius);
    } catch (const fw::CalibrationError& error) {
        throw vpe::common::InputError(args.trueCamera, error.what());
    }
    const fw::testing::LampSurvey survey =
        fw::testing::surveyLampDirections(*trueCamera, *model, sphere, radius, settings);
    if (survey.positions.empty()) {
        throw vpe::common::InputError(args.trueCamera,
                                      "the true camera sees none of the lamp's positions on the " +
                                          std::to_string(radius) + " m sphere");
    }
    const fw::testing::LampSurveyPosition* worst = nullptr;
    for (const auto& p : survey.positions) {
        if (p.errorDeg && (worst == nullptr || *p.errorDeg > *worst->errorDeg)) {
            worst = &p;
        }
    }
    const std::size_t mapped = survey.positions.size() - survey.unmapped();
    std::printf(
        "%s: the bundle's camera against %s, lamp sphere %.3g m %s the true camera: %zu "
        "positions seen (%zu of the grid not), %zu unmapped\n",
        args.bundle.c_str(), args.trueCamera.c_str(), radius,
        model->cameraInsideSphere() ? "around" : "in front of", survey.positions.size(),
        survey.skipped, survey.unmapped());
    if (worst != nullptr) {
        std::printf(
            "direction error over %zu positions: median %.3f°, max %.3f° (azimuth %g°, elevation "
            "%g°, pixel %.1f, %.1f, %.1f° from the sphere's normal)\n",
            mapped, survey.medianErrorDeg(), survey.maxErrorDeg(), worst->azimuthDeg,
            worst->elevationDeg, worst->u, worst->v, worst->incidenceDeg);
    }
    if (args.json) {
        const nlohmann::json report{{"lamp_error_deg_max", survey.maxErrorDeg()},
                                    {"lamp_error_deg_median", survey.medianErrorDeg()},
                                    {"positions", mapped},
                                    {"unmapped", survey.unmapped()}};
        std::cout << report.dump() << "\n";
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::optional<Arguments> args =
            parse(std::vector<std::string>(argv + 1, argv + argc));
        if (!args) {
            std::fputs(kUsage, stderr);
            return 2;
        }
        return run(*args);
    } catch (const vpe::common::InputError& error) {
        std::fprintf(stderr, "vpe_lamp_direction: %s\n", error.what());
        return 2;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_lamp_direction: %s\n", error.what());
        return 1;
    }
}
