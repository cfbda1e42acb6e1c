// SPDX-License-Identifier: MIT
// BoardConfig: reading a board's TOML file (toml++), strictly: unknown keys and wrong types are
// refused with one line naming file:key.
#include "vpe/firmware/board/board_config.h"

#include <charconv>
#include <fstream>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "board/toml_fields.h"

namespace vpe::firmware {

namespace {

using namespace toml_fields;

// Input sections: parsed by their rooms (knobs/, tracking/, osc/, bus/) through
// BoardConfig::section.
const std::set<std::string, std::less<>> kInputSections{"gpio", "camera", "osc", "bus"};

bool parseInt(std::string_view text, int& value) {
    if (text.empty()) {
        return false;
    }
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc{} && end == text.data() + text.size() && value > 0;
}

}  // namespace

std::optional<DisplayMode> parseDisplayMode(std::string_view text) {
    DisplayMode mode;
    const std::size_t x = text.find('x');
    if (x == std::string_view::npos) {
        return std::nullopt;
    }
    std::string_view rest = text.substr(x + 1);
    const std::size_t at = rest.find('@');
    if (at != std::string_view::npos) {
        if (!parseInt(rest.substr(at + 1), mode.refresh)) {
            return std::nullopt;
        }
        rest = rest.substr(0, at);
    }
    if (!parseInt(text.substr(0, x), mode.width) || !parseInt(rest, mode.height)) {
        return std::nullopt;
    }
    return mode;
}

BoardConfig parseBoardConfig(std::string_view text, const std::string& source) {
    toml::table root;
    try {
        root = toml::parse(text, source);
    } catch (const toml::parse_error& error) {
        std::string description(error.description());
        if (const std::size_t newline = description.find('\n'); newline != std::string::npos) {
            description.resize(newline);
        }
        throw BoardConfigError(source + ":" + std::to_string(error.source().begin.line) + ": " +
                               description);
    }
    std::set<std::string, std::less<>> sections{"board", "display", "render", "light", "idle"};
    sections.insert("scan");  // board/scan_config.h: what vpe-player --scan needs
    sections.insert(kInputSections.begin(), kInputSections.end());
    checkKeys(root, source, "", sections);
    for (const std::string& input : kInputSections) {
        optionalTable(root, source, "", input.c_str());
    }

    BoardConfig config;
    config.source = source;
    config.light = parseLightConfig(optionalTable(root, source, "", "light"), source);
    config.idle = parseIdleConfig(optionalTable(root, source, "", "idle"), source);
    if (const toml::table* scan = optionalTable(root, source, "", "scan")) {
        config.scan = parseScanConfig(*scan, source);
    }
    if (const toml::table* board = optionalTable(root, source, "", "board")) {
        checkKeys(*board, source, "board", {"name"});
        config.name = optionalString(*board, source, "board", "name").value_or("");
    }

    const toml::table* display = optionalTable(root, source, "", "display");
    if (display == nullptr) {
        fail(source, "display",
             "missing (a [display] table with backend = \"headless\" or \"kms\")");
    }
    checkKeys(*display, source, "display", {"backend", "device", "connector", "mode", "modeset"});
    const std::optional<std::string> backend =
        optionalString(*display, source, "display", "backend");
    if (!backend) {
        fail(source, "display.backend", "missing (\"headless\" or \"kms\")");
    }
    if (*backend == "headless") {
        config.display.backend = DisplayBackend::kHeadless;
    } else if (*backend == "kms") {
        config.display.backend = DisplayBackend::kKms;
    } else {
        fail(source, "display.backend",
             "expected \"headless\" or \"kms\", got \"" + *backend + "\"");
    }
    if (auto device = optionalString(*display, source, "display", "device")) {
        if (device->empty()) {
            fail(source, "display.device",
                 "is empty (a DRM node such as \"/dev/dri/card0\", or \"auto\")");
        }
        config.display.device = *device;
    }
    if (auto connector = optionalString(*display, source, "display", "connector")) {
        if (connector->empty()) {
            fail(source, "display.connector",
                 "is empty (a name such as \"HDMI-A-1\", or \"auto\")");
        }
        config.display.connector = *connector;
    }
    if (auto mode = optionalString(*display, source, "display", "mode")) {
        if (*mode != "preferred") {
            config.display.mode = parseDisplayMode(*mode);
            if (!config.display.mode) {
                fail(source, "display.mode",
                     "expected \"WxH@Hz\", \"WxH\" or \"preferred\", got \"" + *mode + "\"");
            }
        }
    }

    if (auto modeset = optionalString(*display, source, "display", "modeset")) {
        if (*modeset != "auto" && *modeset != "legacy") {
            fail(source, "display.modeset",
                 "expected \"auto\" or \"legacy\", got \"" + *modeset + "\"");
        }
        config.display.atomic = *modeset == "auto";
    }

    if (const toml::table* render = optionalTable(root, source, "", "render")) {
        checkKeys(*render, source, "render", {"size", "rate"});
        if (auto rate = optionalNumber(*render, source, "render", "rate")) {
            if (*rate < 0 || *rate > 1000) {
                fail(source, "render.rate",
                     "expected frames per second in [0, 1000] (0: unpaced), got " +
                         std::to_string(*rate));
            }
            config.render.rate = *rate;
        }
        if (auto size = optionalString(*render, source, "render", "size")) {
            if (*size != "projector") {
                const std::optional<DisplayMode> parsed = parseDisplayMode(*size);
                if (!parsed || parsed->refresh != 0) {
                    fail(source, "render.size",
                         "expected \"WxH\" or \"projector\", got \"" + *size + "\"");
                }
                config.render.width = parsed->width;
                config.render.height = parsed->height;
            }
        }
    }
    config.document = std::make_shared<const toml::table>(std::move(root));
    return config;
}

const toml::table* BoardConfig::section(std::string_view key) const {
    if (!document) {
        return nullptr;
    }
    const toml::node* node = document->get(key);
    return node == nullptr ? nullptr : node->as_table();
}

BoardConfig loadBoardConfig(const std::filesystem::path& path) {
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
        throw BoardConfigError(path.string() + ": cannot read board file (no such file)");
    }
    if (!std::filesystem::is_regular_file(path, error)) {
        throw BoardConfigError(path.string() + ": cannot read board file (not a regular file)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw BoardConfigError(path.string() + ": cannot read board file (permission denied)");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseBoardConfig(text.str(), path.string());
}

}  // namespace vpe::firmware
