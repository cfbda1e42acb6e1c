// SPDX-License-Identifier: MIT
// Reading a Relight web RTI back and relighting it as OpenLIME does.
#include "vpe/relight_web/relight_web_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::relight_web {

namespace {

nlohmann::json parseInfo(const std::filesystem::path& infoJson) {
    std::ifstream file(infoJson);
    if (!file) {
        throw common::InputError(infoJson, "cannot open (no Relight export here?)");
    }
    std::stringstream text;
    text << file.rdbuf();
    try {
        nlohmann::json info = nlohmann::json::parse(text.str());
        if (!info.is_object()) {
            throw common::InputError(infoJson, "is not a JSON object");
        }
        return info;
    } catch (const nlohmann::json::parse_error& error) {
        throw common::InputError(infoJson, std::string("malformed JSON: ") + error.what());
    }
}

int integerField(const nlohmann::json& info, const char* key, const std::filesystem::path& path,
                 int lo, int hi) {
    const auto it = info.find(key);
    if (it == info.end() || !it->is_number_integer()) {
        throw common::InputError(path, std::string("\"") + key + "\" is missing or not an integer");
    }
    const auto value = it->get<long long>();
    if (value < lo || value > hi) {
        throw common::InputError(path, std::string("\"") + key + "\" = " + std::to_string(value) +
                                           " is outside " + std::to_string(lo) + ".." +
                                           std::to_string(hi));
    }
    return static_cast<int>(value);
}

std::string stringField(const nlohmann::json& info, const char* key,
                        const std::filesystem::path& path) {
    const auto it = info.find(key);
    if (it == info.end() || !it->is_string()) {
        throw common::InputError(path, std::string("\"") + key + "\" is missing or not a string");
    }
    return it->get<std::string>();
}

std::vector<double> numberArray(const nlohmann::json& object, const char* key,
                                const std::filesystem::path& path, std::size_t size) {
    const auto it = object.find(key);
    if (it == object.end() || !it->is_array() || it->size() != size) {
        throw common::InputError(path, std::string("\"") + key + "\" must be an array of " +
                                           std::to_string(size) + " numbers");
    }
    std::vector<double> values;
    for (const auto& v : *it) {
        if (!v.is_number() || !std::isfinite(v.get<double>())) {
            throw common::InputError(
                path, std::string("\"") + key + "\" holds a value that is not a number");
        }
        values.push_back(v.get<double>());
    }
    return values;
}

std::vector<proto::Vec3d> lightsOf(const nlohmann::json& info, const std::filesystem::path& path) {
    std::vector<proto::Vec3d> lights;
    const auto it = info.find("lights");
    if (it == info.end()) {
        return lights;
    }
    if (!it->is_array() || it->size() % 3 != 0) {
        throw common::InputError(path, "\"lights\" must be an array of x, y, z triples");
    }
    const std::vector<double> values = numberArray(info, "lights", path, it->size());
    for (std::size_t i = 0; i < values.size(); i += 3) {
        const std::optional<proto::Vec3d> direction =
            capture::unitDirection(proto::Vec3d{values[i], values[i + 1], values[i + 2]});
        if (!direction) {
            throw common::InputError(
                path, "\"lights\" direction " + std::to_string(i / 3) + " has zero length");
        }
        lights.push_back(*direction);
    }
    return lights;
}

}  // namespace

std::vector<proto::Vec3d> readRelightExportLights(const std::filesystem::path& infoJson) {
    return lightsOf(parseInfo(infoJson), infoJson);
}

RelightWebReader::RelightWebReader(const std::filesystem::path& path)
    : grid_(BilinearLightGrid::kMinResolution) {
    const std::filesystem::path folder =
        std::filesystem::is_directory(path) ? path : path.parent_path();
    const std::filesystem::path infoPath =
        std::filesystem::is_directory(path) ? path / "info.json" : path;
    const nlohmann::json info = parseInfo(infoPath);

    width_ = integerField(info, "width", infoPath, 1, 1 << 16);
    height_ = integerField(info, "height", infoPath, 1, 1 << 16);
    const std::string type = stringField(info, "type", infoPath);
    if (type != "bilinear") {
        throw common::InputError(
            infoPath, "type \"" + type + "\" is not supported: vpe reads bilinear exports only");
    }
    const std::string colorspace = stringField(info, "colorspace", infoPath);
    if (colorspace != "mrgb") {
        throw common::InputError(infoPath, "colorspace \"" + colorspace +
                                               "\" is not supported: vpe reads mrgb exports only");
    }
    if (info.contains("format") && info["format"] != "jpg") {
        throw common::InputError(infoPath, "format " + info["format"].dump() +
                                               " is not supported: vpe reads jpg planes only");
    }
    grid_ = BilinearLightGrid(integerField(info, "resolution", infoPath,
                                           BilinearLightGrid::kMinResolution,
                                           BilinearLightGrid::kMaxResolution));
    const int dimensions = grid_.nodeCount() * 3;
    planes_ = integerField(info, "nplanes", infoPath, 1, dimensions);
    lights_ = lightsOf(info, infoPath);

    const auto materials = info.find("materials");
    if (materials == info.end() || !materials->is_array() || materials->size() != 1 ||
        !(*materials)[0].is_object()) {
        throw common::InputError(infoPath, "\"materials\" must hold exactly one material");
    }
    const auto& material = (*materials)[0];
    const auto count = static_cast<std::size_t>(planes_);
    const std::vector<double> range = numberArray(material, "range", infoPath, count);
    const std::vector<double> scale = numberArray(material, "scale", infoPath, count);
    const std::vector<double> bias = numberArray(material, "bias", infoPath, count);
    for (const double r : range) {
        if (r == 0) {
            throw common::InputError(infoPath,
                                     "\"range\" holds a zero (the basis would divide by it)");
        }
    }

    // OpenLIME's loadBasis: the mean plane is byte/255, the others (byte − 127)/range.
    const std::size_t basisSize = (count + 1) * static_cast<std::size_t>(dimensions);
    const std::vector<double> bytes = numberArray(info, "basis", infoPath, basisSize);
    basis_.resize(basisSize);
    for (std::size_t o = 0; o < basisSize; ++o) {
        if (bytes[o] < 0 || bytes[o] > 255) {
            throw common::InputError(infoPath, "\"basis\" value " + std::to_string(bytes[o]) +
                                                   " at " + std::to_string(o) + " is not a byte");
        }
        const std::size_t plane = o / static_cast<std::size_t>(dimensions);
        basis_[o] = plane == 0 ? static_cast<float>(bytes[o] / 255.0)
                               : static_cast<float>((bytes[o] - 127.0) / range[plane - 1]);
    }

    // Planes: plane_j.jpg holds coefficients 3j, 3j+1, 3j+2 in R, G, B.
    const std::size_t pixels = static_cast<std::size_t>(width_) * height_;
    coefficients_.assign(pixels * count, 0.0f);
    const int jpegs = (planes_ + 2) / 3;
    for (int j = 0; j < jpegs; ++j) {
        const std::filesystem::path planePath = folder / ("plane_" + std::to_string(j) + ".jpg");
        if (!std::filesystem::exists(planePath)) {
            throw common::InputError(planePath, "missing: " + infoPath.filename().string() +
                                                    " declares " + std::to_string(planes_) +
                                                    " planes, " + std::to_string(jpegs) + " JPEGs");
        }
        const image::FloatImage image = image::readImage(planePath);
        if (image.width != width_ || image.height != height_ || image.channels < 3) {
            throw common::InputError(planePath, "is " + std::to_string(image.width) + "x" +
                                                    std::to_string(image.height) + "x" +
                                                    std::to_string(image.channels) + ", expected " +
                                                    std::to_string(width_) + "x" +
                                                    std::to_string(height_) + " RGB");
        }
        for (int c = 0; c < 3 && j * 3 + c < planes_; ++c) {
            const auto k = static_cast<std::size_t>(j * 3 + c);
            for (std::size_t p = 0; p < pixels; ++p) {
                const double value = image.pixels[p * static_cast<std::size_t>(image.channels) +
                                                  static_cast<std::size_t>(c)];
                coefficients_[p * count + k] = static_cast<float>((value - bias[k]) * scale[k]);
            }
        }
    }
}

std::vector<float> RelightWebReader::decode(const proto::Vec3d& towardsLight) const {
    return decode(grid_.weights(towardsLight));
}

std::vector<float> RelightWebReader::decodeNode(int node) const {
    if (node < 0 || node >= grid_.nodeCount()) {
        throw std::out_of_range("light grid node " + std::to_string(node) + " is outside 0.." +
                                std::to_string(grid_.nodeCount() - 1));
    }
    LightGridWeights only;
    only.nodes = {node, node, node, node};
    only.weights = {1.0, 0.0, 0.0, 0.0};
    return decode(only);
}

std::vector<float> RelightWebReader::decode(const LightGridWeights& w) const {
    // The per-light weights OpenLIME's BLN.lightWeights computes on the CPU: the basis
    // blended between the four grid nodes around the light, for the mean and every plane.
    const std::size_t count = static_cast<std::size_t>(planes_);
    const std::size_t dimensions = static_cast<std::size_t>(grid_.nodeCount()) * 3;
    std::vector<float> base((count + 1) * 3, 0.0f);
    for (std::size_t p = 0; p <= count; ++p) {
        for (std::size_t k = 0; k < 3; ++k) {
            double sum = 0;
            for (std::size_t n = 0; n < 4; ++n) {
                const auto node = static_cast<std::size_t>(w.nodes[n]);
                sum += w.weights[n] * static_cast<double>(basis_[p * dimensions + node * 3 + k]);
            }
            base[p * 3 + k] = static_cast<float>(sum);
        }
    }
    const std::size_t pixels = static_cast<std::size_t>(width_) * height_;
    std::vector<float> rgb(pixels * 3);
    for (std::size_t i = 0; i < pixels; ++i) {
        const float* c = &coefficients_[i * count];
        for (std::size_t k = 0; k < 3; ++k) {
            float value = base[k];
            for (std::size_t p = 0; p < count; ++p) {
                value += base[(p + 1) * 3 + k] * c[p];
            }
            rgb[i * 3 + k] = value;
        }
    }
    return rgb;
}

std::vector<float> RelightWebReader::relight(const proto::Vec3d& towardsLight) const {
    std::vector<float> rgb = decode(towardsLight);
    for (float& value : rgb) {
        value = std::clamp(value, 0.0f, 1.0f);
    }
    return rgb;
}

}  // namespace vpe::relight_web
