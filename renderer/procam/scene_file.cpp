// SPDX-License-Identifier: MIT
// Scene files: TOML through toml++ (strict: every key known, every value checked), the object
// through tinyobjloader.
#include "vpe/renderer/procam/scene_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <tiny_obj_loader.h>
#include <toml++/toml.h>
#include <unistd.h>

namespace vpe::renderer::procam {

namespace {

class Section {
public:
    Section(const toml::table* table, std::string source, std::string name,
            std::set<std::string> allowed)
        : table_(table), source_(std::move(source)), name_(std::move(name)) {
        if (table_ == nullptr) {
            return;
        }
        for (const auto& [key, node] : *table_) {
            if (!allowed.contains(std::string(key.str()))) {
                fail(std::string(key.str()), "unknown key");
            }
        }
    }

    bool present() const { return table_ != nullptr; }

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
        throw SceneFileError(source_ + ":" + name_ + (key.empty() ? "" : "." + key) + ": " +
                             problem);
    }

    std::optional<double> number(const char* key, double low, double high) const {
        const toml::node* node = find(key);
        if (node == nullptr) {
            return std::nullopt;
        }
        const auto value = node->value<double>();
        if (!value || !(node->is_floating_point() || node->is_integer())) {
            fail(key, "expected a number");
        }
        if (!std::isfinite(*value) || *value < low || *value > high) {
            fail(key, "outside [" + text(low) + ", " + text(high) + "]");
        }
        return *value;
    }

    double number(const char* key, double fallback, double low, double high) const {
        return number(key, low, high).value_or(fallback);
    }

    std::optional<bool> boolean(const char* key) const {
        const toml::node* node = find(key);
        if (node == nullptr) {
            return std::nullopt;
        }
        if (!node->is_boolean()) {
            fail(key, "expected true or false");
        }
        return node->value<bool>();
    }

    std::optional<std::string> string(const char* key) const {
        const toml::node* node = find(key);
        if (node == nullptr) {
            return std::nullopt;
        }
        if (!node->is_string()) {
            fail(key, "expected a string");
        }
        return *node->value<std::string>();
    }

    // An array of exactly `count` numbers (or `alternative` numbers when given, e.g. 1 or 3).
    std::optional<std::vector<double>> numbers(const char* key, std::size_t count,
                                               std::size_t alternative = 0) const {
        const toml::node* node = find(key);
        if (node == nullptr) {
            return std::nullopt;
        }
        const toml::array* array = node->as_array();
        if (array == nullptr || (array->size() != count && array->size() != alternative)) {
            fail(key, "expected an array of " + std::to_string(count) +
                          (alternative ? " or " + std::to_string(alternative) : "") + " numbers");
        }
        std::vector<double> values;
        for (const toml::node& item : *array) {
            const auto value = item.value<double>();
            if (!value || !std::isfinite(*value) ||
                !(item.is_integer() || item.is_floating_point())) {
                fail(key, "expected finite numbers");
            }
            values.push_back(*value);
        }
        return values;
    }

    // An array of 2..1024 finite numbers.
    std::optional<std::vector<double>> sampledNumbers(const char* key) const {
        const toml::node* node = find(key);
        if (node == nullptr) {
            return std::nullopt;
        }
        const toml::array* array = node->as_array();
        if (array == nullptr || array->size() < 2 || array->size() > 1024) {
            fail(key, "expected an array of 2 to 1024 numbers");
        }
        return numbers(key, array->size());
    }

    std::vector<double> required(const char* key, std::size_t count) const {
        auto values = numbers(key, count);
        if (!values) {
            fail(key, "missing");
        }
        return *values;
    }

private:
    const toml::node* find(const char* key) const {
        return table_ == nullptr ? nullptr : table_->get(key);
    }
    static std::string text(double v) {
        std::ostringstream out;
        out << v;
        return out.str();
    }

    const toml::table* table_;
    std::string source_, name_;
};

template <std::size_t N>
std::array<double, N> toArray(const std::vector<double>& values) {
    std::array<double, N> out{};
    std::copy_n(values.begin(), N, out.begin());
    return out;
}

std::array<double, 3> rgbOf(const Section& s, const char* key, std::array<double, 3> fallback) {
    const auto values = s.numbers(key, 3, 1);
    if (!values) {
        return fallback;
    }
    return values->size() == 1 ? std::array<double, 3>{(*values)[0], (*values)[0], (*values)[0]}
                               : toArray<3>(*values);
}

RigidPose poseOf(const Section& s) {
    RigidPose pose;
    pose.t = toArray<3>(s.required("position", 3));
    if (const auto r = s.numbers("rotation", 9)) {
        pose.R = toArray<9>(*r);
    }
    return pose;
}

proto::PinholeCamera cameraOf(const Section& s) {
    proto::PinholeCamera c;
    const auto size = s.required("size", 2);
    c.width = static_cast<int>(size[0]);
    c.height = static_cast<int>(size[1]);
    if (size[0] != c.width || size[1] != c.height) {
        s.fail("size", "expected whole numbers of pixels");
    }
    c.K = toArray<9>(s.required("K", 9));
    if (const auto d = s.numbers("distortion", 5)) {
        c.distortion = toArray<5>(*d);
    }
    c.R = toArray<9>(s.required("R", 9));
    c.T = toArray<3>(s.required("T", 3));
    if (auto problem = proto::checkCamera(c); !problem.empty()) {
        s.fail("", problem);
    }
    return c;
}

std::uint64_t seedOf(const Section& s, const char* key) {
    return static_cast<std::uint64_t>(s.number(key, 1, 0, 9.0e15));
}

// TOML arrays of numbers, written with enough digits to read back the same doubles.
toml::array arrayOf(std::span<const double> values) {
    toml::array array;
    for (const double v : values) {
        array.push_back(v);
    }
    return array;
}

toml::table cameraTable(const proto::PinholeCamera& c) {
    return toml::table{{"size", toml::array{c.width, c.height}},
                       {"K", arrayOf(c.K)},
                       {"distortion", arrayOf(c.distortion)},
                       {"R", arrayOf(c.R)},
                       {"T", arrayOf(c.T)}};
}

}  // namespace

ScreenObject readObjectMesh(const std::filesystem::path& path) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path.string(), config)) {
        std::string error = reader.Error();
        std::replace(error.begin(), error.end(), '\n', ' ');
        throw SceneFileError(path.string() + ": cannot read the object's OBJ (" +
                             (error.empty() ? "no such file" : error) + ")");
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    ScreenObject object;
    std::map<std::tuple<int, int, int>, std::uint32_t> vertices;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        for (const tinyobj::index_t& index : shape.mesh.indices) {
            if (index.normal_index < 0 || index.texcoord_index < 0) {
                throw SceneFileError(path.string() +
                                     ": every vertex needs a normal and a texture coordinate "
                                     "(f v/vt/vn)");
            }
            const auto key =
                std::tuple{index.vertex_index, index.normal_index, index.texcoord_index};
            auto [it, added] =
                vertices.emplace(key, static_cast<std::uint32_t>(object.positions.size()));
            if (added) {
                const auto v = static_cast<std::size_t>(index.vertex_index);
                const auto n = static_cast<std::size_t>(index.normal_index);
                const auto t = static_cast<std::size_t>(index.texcoord_index);
                object.positions.push_back({attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                                            attrib.vertices[3 * v + 2]});
                object.normals.push_back(
                    {attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]});
                object.uvs.push_back({attrib.texcoords[2 * t], attrib.texcoords[2 * t + 1]});
            }
            object.indices.push_back(it->second);
        }
    }
    if (auto problem = checkRenderMesh(object.view()); !problem.empty()) {
        throw SceneFileError(path.string() + ": " + problem);
    }
    return object;
}

SceneFile readSceneFile(const std::filesystem::path& path) {
    const std::string source = path.string();
    toml::table root;
    try {
        root = toml::parse_file(source);
    } catch (const toml::parse_error& error) {
        std::error_code code;
        if (!std::filesystem::exists(path, code)) {
            throw SceneFileError(source + ": cannot open the scene (no such file)");
        }
        std::string what(error.description());
        throw SceneFileError(source + ":" + std::to_string(error.source().begin.line) +
                             ": not a scene file (" + what + ")");
    }
    for (const auto& [key, node] : root) {
        static const std::set<std::string> sections{"object",    "albedo", "board",
                                                    "projector", "camera", "room"};
        if (!sections.contains(std::string(key.str())) || !node.is_table()) {
            throw SceneFileError(source + ":" + std::string(key.str()) +
                                 ": unknown section (object, albedo, board, projector, camera, "
                                 "room)");
        }
    }
    SceneFile file;
    ProcamScene& scene = file.scene;

    const Section object(root["object"].as_table(), source, "object",
                         {"mesh", "position", "rotation"});
    if (object.present()) {
        const auto mesh = object.string("mesh");
        if (!mesh) {
            object.fail("mesh", "missing (the object's OBJ, relative to this file)");
        }
        file.meshPath = path.parent_path() / *mesh;
        scene.object = readObjectMesh(file.meshPath);
        scene.object->pose = poseOf(object);
    }
    const Section albedo(root["albedo"].as_table(), source, "albedo",
                         {"base", "foot_shade", "stain_strength", "stain_scale", "seed"});
    scene.albedo.base = rgbOf(albedo, "base", scene.albedo.base);
    scene.albedo.footShade = albedo.number("foot_shade", 0.0, 0.0, 0.99);
    scene.albedo.stainStrength = albedo.number("stain_strength", 0.0, 0.0, 0.99);
    scene.albedo.stainScale = albedo.number("stain_scale", 0.02, 1e-4, 10.0);
    scene.albedo.seed = seedOf(albedo, "seed");

    const Section board(
        root["board"].as_table(), source, "board",
        {"squares", "square_m", "margin_m", "light", "dark", "position", "rotation"});
    if (board.present()) {
        CheckerBoard b;
        if (const auto squares = board.numbers("squares", 2)) {
            b.squaresX = static_cast<int>((*squares)[0]);
            b.squaresY = static_cast<int>((*squares)[1]);
        }
        b.squareM = board.number("square_m", b.squareM, 1e-4, 1.0);
        b.marginM = board.number("margin_m", b.marginM, 0.0, 1.0);
        b.light = rgbOf(board, "light", b.light);
        b.dark = rgbOf(board, "dark", b.dark);
        b.pose = poseOf(board);
        scene.board = b;
    }

    const Section projector(root["projector"].as_table(), source, "projector",
                            {"size", "K", "distortion", "R", "T", "gamma", "curve_red",
                             "curve_green", "curve_blue", "black_level", "mixing",
                             "peak_irradiance", "blur_px", "dlp_exposure_frames", "dlp_bit_order"});
    if (!projector.present()) {
        throw SceneFileError(source + ": projector: missing section");
    }
    scene.projector.camera = cameraOf(projector);
    scene.projector.response =
        proto::ResponseFunction::gamma(rgbOf(projector, "gamma", {2.2, 2.2, 2.2}));
    // Or sampled curves (all three), sample i of N at level i / (N − 1): a response that is not
    // a gamma, as real projectors' are.
    const auto curve = [&](const char* key) { return projector.sampledNumbers(key); };
    const auto red = curve("curve_red"), green = curve("curve_green"), blue = curve("curve_blue");
    if (red || green || blue) {
        if (!red || !green || !blue) {
            projector.fail(red ? (green ? "curve_blue" : "curve_green") : "curve_red",
                           "missing: curves are given for all three channels or none");
        }
        std::array<std::vector<double>, 3> levels, outputs{*red, *green, *blue};
        for (std::size_t c = 0; c < 3; ++c) {
            for (std::size_t i = 0; i < outputs[c].size(); ++i) {
                levels[c].push_back(static_cast<double>(i) /
                                    static_cast<double>(outputs[c].size() - 1));
            }
        }
        try {
            scene.projector.response = proto::ResponseFunction::sampled(levels, outputs);
        } catch (const std::invalid_argument& error) {
            projector.fail("curve_red", error.what());
        }
    }
    if (const auto mixing = projector.numbers("mixing", 9)) {
        scene.projector.mixing = toArray<9>(*mixing);
    }
    scene.projector.blackLevel = rgbOf(projector, "black_level", scene.projector.blackLevel);
    scene.projector.peakIrradiance = projector.number("peak_irradiance", 1.0, 1e-6, 1e6);
    scene.projector.blurPixels = projector.number("blur_px", 0.7, 0.0, 20.0);
    // A DLP's bit-planes against a camera exposing this many frame periods (0: off).
    DlpTiming& dlp = scene.projector.dlp;
    dlp.exposureFrames = projector.number("dlp_exposure_frames", 0.0, 0.0, 100.0);
    const std::string order = projector.string("dlp_bit_order").value_or("msb_first");
    if (order != "msb_first" && order != "lsb_first") {
        projector.fail("dlp_bit_order", "'" + order + "' is not msb_first or lsb_first");
    }
    dlp.order = order == "lsb_first" ? DlpBitOrder::kLsbFirst : DlpBitOrder::kMsbFirst;

    const Section camera(
        root["camera"].as_table(), source, "camera",
        {"size", "K", "distortion", "R", "T", "exposure", "response", "gamma", "full_well",
         "read_noise", "black_level", "bits", "samples", "monochrome", "seed"});
    if (!camera.present()) {
        throw SceneFileError(source + ": camera: missing section");
    }
    SimulatedCamera& c = file.camera;
    c.camera = cameraOf(camera);
    c.exposure = camera.number("exposure", 1.0, 1e-9, 1e9);
    const std::string response = camera.string("response").value_or("linear");
    if (response != "linear" && response != "gamma") {
        camera.fail("response", "'" + response + "' is not linear or gamma");
    }
    c.response = response == "gamma" ? CameraResponse::kGamma : CameraResponse::kLinear;
    c.gamma = camera.number("gamma", 2.2, 0.1, 9.9);
    c.fullWellElectrons = camera.number("full_well", c.fullWellElectrons, 0.0, 1e9);
    c.readNoiseElectrons = camera.number("read_noise", c.readNoiseElectrons, 0.0, 1e6);
    c.blackLevel = camera.number("black_level", 0.0, 0.0, 0.49);
    c.bits = static_cast<int>(camera.number("bits", 8, 8, 10));
    c.samples = static_cast<int>(camera.number("samples", 2, 1, 8));
    c.monochrome = camera.boolean("monochrome").value_or(true);
    c.seed = seedOf(camera, "seed");

    const Section room(root["room"].as_table(), source, "room",
                       {"ambient", "interreflection", "interreflection_grid"});
    scene.room.ambient = rgbOf(room, "ambient", scene.room.ambient);
    scene.room.interreflection = room.boolean("interreflection").value_or(true);
    scene.room.interreflectionGrid =
        static_cast<int>(room.number("interreflection_grid", 48, 4, 256));

    if (auto problem = checkProcamScene(scene); !problem.empty()) {
        throw SceneFileError(source + ": " + problem);
    }
    if (auto problem = checkSimulatedCamera(c); !problem.empty()) {
        throw SceneFileError(source + ": " + problem);
    }
    return file;
}

void writeSceneFile(const std::filesystem::path& path, const ProcamScene& scene,
                    const SimulatedCamera& camera, const std::string& objectMesh) {
    toml::table root;
    if (scene.object) {
        root.insert("object", toml::table{{"mesh", objectMesh},
                                          {"position", arrayOf(scene.object->pose.t)},
                                          {"rotation", arrayOf(scene.object->pose.R)}});
    }
    const PlasterAlbedo& a = scene.albedo;
    root.insert("albedo", toml::table{{"base", arrayOf(a.base)},
                                      {"foot_shade", a.footShade},
                                      {"stain_strength", a.stainStrength},
                                      {"stain_scale", a.stainScale},
                                      {"seed", static_cast<std::int64_t>(a.seed)}});
    if (scene.board) {
        const CheckerBoard& b = *scene.board;
        root.insert("board", toml::table{{"squares", toml::array{b.squaresX, b.squaresY}},
                                         {"square_m", b.squareM},
                                         {"margin_m", b.marginM},
                                         {"light", arrayOf(b.light)},
                                         {"dark", arrayOf(b.dark)},
                                         {"position", arrayOf(b.pose.t)},
                                         {"rotation", arrayOf(b.pose.R)}});
    }
    const SimulatedProjector& p = scene.projector;
    toml::table projector = cameraTable(p.camera);
    if (p.response.isGamma()) {
        // A gamma's exponent is what its output says at one level: level^γ = output.
        std::array<double, 3> gamma{};
        for (int c = 0; c < 3; ++c) {
            gamma[static_cast<std::size_t>(c)] =
                std::log(p.response.output(c, 0.5)) / std::log(0.5);
        }
        projector.insert("gamma", arrayOf(gamma));
    } else {
        // Sampled at 33 levels: the curves a scene file can hold are piecewise linear through
        // their samples, so a curve made here from 33 or fewer even samples reads back exactly.
        const char* keys[3] = {"curve_red", "curve_green", "curve_blue"};
        for (int c = 0; c < 3; ++c) {
            std::vector<double> samples;
            for (int i = 0; i <= 32; ++i) {
                samples.push_back(p.response.output(c, i / 32.0));
            }
            projector.insert(keys[c], arrayOf(samples));
        }
    }
    if (p.mixing != std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}) {
        projector.insert("mixing", arrayOf(p.mixing));
    }
    projector.insert("black_level", arrayOf(p.blackLevel));
    projector.insert("peak_irradiance", p.peakIrradiance);
    projector.insert("blur_px", p.blurPixels);
    if (p.dlp.enabled()) {
        projector.insert("dlp_exposure_frames", p.dlp.exposureFrames);
        projector.insert("dlp_bit_order",
                         p.dlp.order == DlpBitOrder::kLsbFirst ? "lsb_first" : "msb_first");
    }
    root.insert("projector", projector);
    toml::table c = cameraTable(camera.camera);
    c.insert("exposure", camera.exposure);
    c.insert("response", camera.response == CameraResponse::kGamma ? "gamma" : "linear");
    c.insert("gamma", camera.gamma);
    c.insert("full_well", camera.fullWellElectrons);
    c.insert("read_noise", camera.readNoiseElectrons);
    if (camera.blackLevel > 0) {
        c.insert("black_level", camera.blackLevel);
    }
    c.insert("bits", camera.bits);
    c.insert("samples", camera.samples);
    c.insert("monochrome", camera.monochrome);
    c.insert("seed", static_cast<std::int64_t>(camera.seed));
    root.insert("camera", c);
    root.insert("room", toml::table{{"ambient", arrayOf(scene.room.ambient)},
                                    {"interreflection", scene.room.interreflection},
                                    {"interreflection_grid", scene.room.interreflectionGrid}});

    std::ostringstream text;
    text << "# vpe simulated installation (renderer/procam/README.md): room frame in metres;\n"
            "# cameras map room points X to R·X + T (OpenCV), K row-major.\n"
         << toml::toml_formatter(root) << "\n";
    const std::filesystem::path temporary = path.string() + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(temporary, std::ios::binary);
        out << text.str();
        if (!out.flush()) {
            std::filesystem::remove(temporary);
            throw SceneFileError(path.string() + ": cannot write the scene");
        }
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) {
        std::filesystem::remove(temporary);
        throw SceneFileError(path.string() + ": cannot write the scene (" + error.message() + ")");
    }
}

}  // namespace vpe::renderer::procam
