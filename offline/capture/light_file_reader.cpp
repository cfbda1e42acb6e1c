// SPDX-License-Identifier: MIT
// RTI .lp light file reader.
#include "vpe/capture/light_file_reader.h"

#include <algorithm>
#include <cmath>

#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::capture {

namespace {

constexpr long kMaxImages = 100000;

}  // namespace

Capture parseLightFile(std::string_view text, const std::filesystem::path& source) {
    const std::vector<text::Line> allLines = text::splitLines(text);
    std::vector<text::Line> lines;
    for (const text::Line& line : allLines) {
        if (!line.text.empty()) {
            lines.push_back(line);
        }
    }
    if (lines.empty()) {
        throw common::InputError(source, 1, "empty light file: expected the number of images");
    }
    const std::vector<std::string_view> header = text::splitFields(lines.front().text);
    const std::optional<long> declared =
        header.size() == 1 ? text::parseInteger(header[0]) : std::nullopt;
    if (!declared) {
        throw common::InputError(
            source, lines.front().number,
            "expected the number of images, found '" + std::string(lines.front().text) + "'");
    }
    if (*declared <= 0 || *declared > kMaxImages) {
        throw common::InputError(source, lines.front().number,
                                 "image count " + std::to_string(*declared) +
                                     " is out of range (1.." + std::to_string(kMaxImages) + ")");
    }
    const long listed = static_cast<long>(lines.size()) - 1;
    if (listed != *declared) {
        // Too many: point at the first line beyond the count; too few: at the count itself.
        const int line = listed > *declared ? lines[static_cast<std::size_t>(*declared) + 1].number
                                            : lines.front().number;
        throw common::InputError(source, line,
                                 "declares " + std::to_string(*declared) + " images but lists " +
                                     std::to_string(listed));
    }

    Capture capture;
    capture.source = source;
    capture.lightKind = LightKind::kDirectional;
    const std::filesystem::path folder = source.parent_path();
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const text::Line& line = lines[i];
        const std::vector<std::string_view> fields = text::splitFields(line.text);
        if (fields.size() < 4) {
            throw common::InputError(
                source, line.number,
                "expected 'image x y z', found '" + std::string(line.text) + "'");
        }
        double xyz[3];
        for (int axis = 0; axis < 3; ++axis) {
            const std::string_view field =
                fields[fields.size() - 3 + static_cast<std::size_t>(axis)];
            const std::optional<double> value = text::parseNumber(field);
            if (!value) {
                throw common::InputError(
                    source, line.number,
                    "light " + std::string("xyz").substr(static_cast<std::size_t>(axis), 1) +
                        " component '" + std::string(field) + "' is not a number");
            }
            xyz[axis] = *value;
        }
        const std::optional<Vec3d> direction = unitDirection(Vec3d{xyz[0], xyz[1], xyz[2]});
        if (!direction) {
            throw common::InputError(source, line.number, "zero-length light vector");
        }
        // The image path is everything before the three numbers, so names may hold spaces.
        const char* nameBegin = fields.front().data();
        const char* nameEnd = fields[fields.size() - 4].data() + fields[fields.size() - 4].size();
        const std::string name(nameBegin, static_cast<std::size_t>(nameEnd - nameBegin));
        CaptureImage image;
        image.file = folder / std::filesystem::path(name).make_preferred();
        image.light = *direction;
        image.line = line.number;
        capture.images.push_back(std::move(image));
    }
    return capture;
}

Capture readLightFile(const std::filesystem::path& path) {
    Capture capture = parseLightFile(text::readTextFile(path, "light file"), path);
    const std::filesystem::path normals = path.parent_path() / "normals.png";
    if (std::filesystem::exists(normals)) {
        capture.normalMap = normals;
        capture.normalEncoding = NormalEncoding::kOffsetRgb;
    }
    return capture;
}

}  // namespace vpe::capture
