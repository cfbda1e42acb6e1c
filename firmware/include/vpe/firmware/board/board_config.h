// SPDX-License-Identifier: MIT
// BoardConfig: one board's configuration, read from a TOML file in boards/ (boards/README.md).
// Unknown keys are refused and every value's type is checked; errors are one line naming the
// file and the key: "boards/rpi4.toml:display.mode: expected \"WxH@Hz\" or \"preferred\", got
// \"1080p\"".
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/board/scan_config.h"
#include "vpe/proto/input_error.h"

namespace vpe::firmware {

class BoardConfigError : public proto::InputError {
public:
    using proto::InputError::InputError;
};

enum class DisplayBackend { kHeadless, kKms };

// A display mode: width × height, refresh in Hz (0: any refresh rate of that size).
struct DisplayMode {
    int width = 0;
    int height = 0;
    int refresh = 0;
};

struct DisplayConfig {
    DisplayBackend backend = DisplayBackend::kHeadless;
    std::string device = "/dev/dri/card0";  // kms: the DRM device node
    std::string connector = "auto";         // kms: "HDMI-A-1", … or "auto" (first connected)
    std::optional<DisplayMode> mode;        // kms: empty = the connector's preferred mode
    bool atomic = true;  // kms: modeset = "auto" (atomic when the device has it) or "legacy"
};

struct RenderConfig {
    // headless: the render target's size; empty = the bundle projector's size.
    std::optional<int> width, height;
    // headless: frames per second paced by a timer (KMS is paced by vsync); 0 = unpaced.
    double rate = 60.0;
};

struct BoardConfig {
    std::string name;    // [board] name (informative)
    std::string source;  // the file, for errors from the sections parsed later
    DisplayConfig display;
    RenderConfig render;
    LightConfig light;
    IdleConfig idle;
    // [scan]: what vpe-player --scan needs; empty when the section is absent (no scan).
    std::optional<ScanConfig> scan;
    // The input sections ([gpio], [camera], [osc], [bus]) are parsed by their own rooms (knobs/,
    // tracking/, osc/, bus/) from the document kept here; nullptr when the section is absent.
    const toml::table* section(std::string_view key) const;
    std::shared_ptr<const toml::table> document;
};

// Parses "1920x1080" (refresh 0) or "1920x1080@60"; nullopt when malformed or not positive.
std::optional<DisplayMode> parseDisplayMode(std::string_view text);

// Parses a board file's text; `source` names it in errors. Throws BoardConfigError.
BoardConfig parseBoardConfig(std::string_view text, const std::string& source);

// Reads and parses a board file. Throws BoardConfigError ("FILE: cannot read (No such file …)").
BoardConfig loadBoardConfig(const std::filesystem::path& path);

}  // namespace vpe::firmware
