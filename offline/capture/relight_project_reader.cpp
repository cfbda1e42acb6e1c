// SPDX-License-Identifier: MIT
// RelightLab project (.relight) reader.
#include "vpe/capture/relight_project_reader.h"

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::capture {

namespace {

Vec3d directionAt(const nlohmann::json& directions, std::size_t i,
                  const std::filesystem::path& source) {
    const nlohmann::json& entry = directions[i];
    const std::string where = "dome.directions[" + std::to_string(i) + "]";
    if (!entry.is_object()) {
        throw common::InputError(source, where + " is not an {x, y, z} object");
    }
    double xyz[3];
    const char* keys[3] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
        const auto it = entry.find(keys[axis]);
        if (it == entry.end() || !it->is_number()) {
            throw common::InputError(source,
                                     where + "." + keys[axis] + " is missing or not a number");
        }
        xyz[axis] = it->get<double>();
    }
    const std::optional<Vec3d> direction = unitDirection(Vec3d{xyz[0], xyz[1], xyz[2]});
    if (!direction) {
        throw common::InputError(source, where + " has zero length");
    }
    return *direction;
}

}  // namespace

Capture parseRelightProject(std::string_view text, const std::filesystem::path& source) {
    nlohmann::json project;
    try {
        project = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& error) {
        throw common::InputError(source, std::string("malformed JSON: ") + error.what());
    }
    if (!project.is_object()) {
        throw common::InputError(source, "is not a JSON object (a RelightLab project is)");
    }
    const auto images = project.find("images");
    if (images == project.end() || !images->is_array() || images->empty()) {
        throw common::InputError(source, "\"images\" is missing or empty");
    }
    const auto dome = project.find("dome");
    if (dome == project.end() || !dome->is_object()) {
        throw common::InputError(source,
                                 "\"dome\" is missing: the project has no light directions");
    }
    // "spherical" and "lights3d" domes place lights at positions in millimetres; only the
    // directional configuration says what vpe's directional capture means.
    const std::string configuration = dome->value("lightConfiguration", "directional");
    if (configuration != "directional") {
        throw common::InputError(source,
                                 "dome.lightConfiguration \"" + configuration +
                                     "\" is not supported: vpe reads directional domes only");
    }
    const auto directions = dome->find("directions");
    if (directions == dome->end() || !directions->is_array()) {
        throw common::InputError(source, "dome.directions is missing");
    }

    std::filesystem::path folder = source.parent_path();
    if (const auto it = project.find("folder"); it != project.end()) {
        if (!it->is_string()) {
            throw common::InputError(source, "\"folder\" is not a string");
        }
        folder /= std::filesystem::path(it->get<std::string>()).make_preferred();
    }

    Capture capture;
    capture.source = source;
    capture.lightKind = LightKind::kDirectional;
    std::size_t lit = 0;  // index into dome.directions: one per image not skipped
    for (std::size_t i = 0; i < images->size(); ++i) {
        const nlohmann::json& image = (*images)[i];
        const auto filename = image.is_object() ? image.find("filename") : image.end();
        if (!image.is_object() || filename == image.end() || !filename->is_string()) {
            throw common::InputError(source,
                                     "images[" + std::to_string(i) + "] has no \"filename\"");
        }
        if (image.value("skip", false)) {
            continue;
        }
        if (lit >= directions->size()) {
            throw common::InputError(source, "dome.directions holds " +
                                                 std::to_string(directions->size()) +
                                                 " directions but more images are not skipped");
        }
        const Vec3d light = directionAt(*directions, lit++, source);
        if (!image.value("visible", true)) {
            continue;
        }
        CaptureImage entry;
        entry.file = folder / std::filesystem::path(filename->get<std::string>()).make_preferred();
        entry.light = light;
        capture.images.push_back(std::move(entry));
    }
    if (lit != directions->size()) {
        throw common::InputError(
            source, "dome.directions holds " + std::to_string(directions->size()) +
                        " directions for " + std::to_string(lit) + " images not skipped");
    }
    if (capture.images.empty()) {
        throw common::InputError(source, "every image is skipped or hidden");
    }
    return capture;
}

Capture readRelightProject(const std::filesystem::path& path) {
    return parseRelightProject(text::readTextFile(path, "RelightLab project"), path);
}

}  // namespace vpe::capture
