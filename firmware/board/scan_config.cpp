// SPDX-License-Identifier: MIT
// The [scan] section, read strictly with the shared board-file helpers.
#include "vpe/firmware/board/scan_config.h"

#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

#include "board/toml_fields.h"

namespace vpe::firmware {

namespace {

using namespace toml_fields;

constexpr const char* kSection = "scan";

bool isPowerOfTwo(int value) {
    return value > 0 && (value & (value - 1)) == 0;
}

}  // namespace

ScanConfig parseScanConfig(const toml::table& scan, const std::string& source) {
    checkKeys(scan, source, kSection,
              {"latency_ms", "settle_ms", "retries", "retry_wait_ms", "exposure_us",
               "analogue_gain", "colour_gains", "camera_size", "phase_period", "phase_steps",
               "min_contrast", "min_lit_fraction", "tolerance", "radiometry", "radiometry_levels",
               "simulate", "simulated_latency_ms", "out"});
    ScanConfig config;
    config.latencyMs =
        numberIn(scan, source, kSection, "latency_ms", 0.0, false, 10000.0, config.latencyMs);
    if (scan.contains("settle_ms")) {
        config.settleMs = numberIn(scan, source, kSection, "settle_ms", 0.0, false, 60000.0, 0.0);
    }
    config.retries = integerIn(scan, source, kSection, "retries", 0, 20, config.retries);
    config.retryWaitMs =
        numberIn(scan, source, kSection, "retry_wait_ms", 0.0, true, 10000.0, config.retryWaitMs);
    config.exposureUs =
        integerIn(scan, source, kSection, "exposure_us", 1, 1'000'000, config.exposureUs);
    config.analogueGain =
        numberIn(scan, source, kSection, "analogue_gain", 1.0, false, 64.0, config.analogueGain);
    if (const toml::node* node = scan.get("colour_gains")) {
        const toml::array* gains = node->as_array();
        if (gains == nullptr || gains->size() != 2 || !(*gains)[0].is_number() ||
            !(*gains)[1].is_number()) {
            fail(source, "scan.colour_gains",
                 std::string("expected [red, blue] numbers, got ") + typeName(*node));
        }
        config.colourGains =
            std::array<double, 2>{*(*gains)[0].value<double>(), *(*gains)[1].value<double>()};
        for (const double gain : *config.colourGains) {
            if (!(gain > 0.0 && gain <= 32.0)) {
                fail(source, "scan.colour_gains",
                     "expected [red, blue] gains in (0, 32], got " + numberText(gain));
            }
        }
    }
    if (auto size = optionalString(scan, source, kSection, "camera_size")) {
        const std::optional<DisplayMode> parsed = parseDisplayMode(*size);
        if (!parsed || parsed->refresh != 0 || parsed->width > 16384 || parsed->height > 16384) {
            fail(source, "scan.camera_size",
                 "expected \"WxH\" (at most 16384x16384), got \"" + *size + "\"");
        }
        config.cameraWidth = parsed->width;
        config.cameraHeight = parsed->height;
    }
    config.phasePeriod =
        integerIn(scan, source, kSection, "phase_period", 8, 1024, config.phasePeriod);
    if (!isPowerOfTwo(config.phasePeriod)) {
        fail(source, "scan.phase_period",
             "expected a power of two in 8…1024, got " + std::to_string(config.phasePeriod));
    }
    config.phaseSteps = integerIn(scan, source, kSection, "phase_steps", 3, 64, config.phaseSteps);
    config.minContrast =
        numberIn(scan, source, kSection, "min_contrast", 0.0, true, 1.0, config.minContrast);
    config.minLitFraction =
        numberIn(scan, source, kSection, "min_lit_fraction", 0.0, true, 1.0, config.minLitFraction);
    if (auto tolerance = optionalNumber(scan, source, kSection, "tolerance")) {
        if (!(*tolerance >= 0.0 && *tolerance < 1.0)) {
            fail(source, "scan.tolerance",
                 "expected a number in [0, 1), got " + numberText(*tolerance));
        }
        config.tolerance = *tolerance;
    }
    config.radiometry =
        optionalBool(scan, source, kSection, "radiometry").value_or(config.radiometry);
    config.radiometryLevels =
        integerIn(scan, source, kSection, "radiometry_levels", 2, 64, config.radiometryLevels);
    if (auto simulate = optionalString(scan, source, kSection, "simulate")) {
        if (simulate->empty()) {
            fail(source, "scan.simulate",
                 "is empty (a scene file such as \"installation.toml\", relative to this file)");
        }
        const std::filesystem::path path(*simulate);
        config.simulate =
            path.is_absolute()
                ? path
                : (std::filesystem::path(source).parent_path() / path).lexically_normal();
    }
    if (auto out = optionalString(scan, source, kSection, "out")) {
        if (out->empty()) {
            fail(source, "scan.out",
                 "is empty (the folder the control page's scans are written to)");
        }
        const std::filesystem::path path(*out);
        config.out = path.is_absolute()
                         ? path
                         : (std::filesystem::path(source).parent_path() / path).lexically_normal();
    }
    if (scan.contains("simulated_latency_ms")) {
        if (!config.simulate) {
            fail(source, "scan.simulated_latency_ms",
                 "only with scan.simulate (a real projector's latency is its own)");
        }
        config.simulatedLatencyMs =
            numberIn(scan, source, kSection, "simulated_latency_ms", 0.0, false, 10000.0, 0.0);
    }
    return config;
}

}  // namespace vpe::firmware
