// SPDX-License-Identifier: MIT
// KnobsConfig: the names of axes and actions, and the [gpio] section's strict reader.
#include "vpe/firmware/knobs/knobs_config.h"

#include <cstdio>
#include <map>
#include <optional>

#include "board/toml_fields.h"

namespace vpe::firmware::knobs {

const char* knobAxisName(KnobAxis axis) {
    switch (axis) {
        case KnobAxis::kAzimuth:
            return "azimuth";
        case KnobAxis::kElevation:
            return "elevation";
        case KnobAxis::kDistance:
            return "distance";
    }
    return "unknown";
}

const char* buttonActionName(ButtonAction action) {
    switch (action) {
        case ButtonAction::kNextPreset:
            return "next-preset";
        case ButtonAction::kPreviousPreset:
            return "previous-preset";
        case ButtonAction::kReset:
            return "reset";
    }
    return "unknown";
}

namespace {

using namespace toml_fields;

// Line offsets are u32 in the kernel; this bound only catches typos (no SoC has more lines on
// one chip); a line the chip lacks is refused when the player requests it.
constexpr long long kMaxLineOffset = 65535;
// The kernel keeps 31 characters of a consumer label (GPIO_MAX_NAME_SIZE = 32 with the NUL).
constexpr std::size_t kMaxConsumerLength = 31;

// 0.5, 20, -3: numbers in messages as the board file would write them.
std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

// Every line used so far, with the key that took it, to refuse a line used twice.
class LineRegistry {
public:
    explicit LineRegistry(const std::string& source) : source_(source) {}

    unsigned take(const toml::table& table, const std::string& section, const char* key) {
        const std::string name = qualified(section, key);
        const std::optional<long long> offset = optionalInteger(table, source_, section, key);
        if (!offset) {
            fail(source_, name, "missing (a line offset on the chip, e.g. 17 for GPIO17)");
        }
        if (*offset < 0 || *offset > kMaxLineOffset) {
            fail(source_, name,
                 "expected a line offset from 0 to " + std::to_string(kMaxLineOffset) + ", got " +
                     std::to_string(*offset));
        }
        const auto line = static_cast<unsigned>(*offset);
        if (const auto used = users_.find(line); used != users_.end()) {
            fail(source_, name,
                 "line " + std::to_string(line) + " is already used by " + used->second);
        }
        users_.emplace(line, name);
        return line;
    }

private:
    const std::string& source_;
    std::map<unsigned, std::string> users_;
};

double readNumberIn(const toml::table& table, const std::string& source, const std::string& section,
                    const char* key, double fallback, double low, double high, const char* what) {
    const std::optional<double> value = optionalNumber(table, source, section, key);
    if (!value) {
        return fallback;
    }
    if (*value < low || *value > high) {
        fail(source, qualified(section, key),
             std::string("expected ") + what + ", got " + numberText(*value));
    }
    return *value;
}

AccelerationCurve readAcceleration(const toml::table& table, const std::string& source,
                                   const std::string& section) {
    AccelerationCurve curve;
    curve.maxFactor = 4;  // written at all: on
    curve.slowMs = readNumberIn(table, source, section, "slow_ms", curve.slowMs, 0, 10000,
                                "milliseconds from 0 to 10000");
    curve.fastMs = readNumberIn(table, source, section, "fast_ms", curve.fastMs, 0, 10000,
                                "milliseconds from 0 to 10000");
    curve.maxFactor = readNumberIn(table, source, section, "max_factor", curve.maxFactor, 1, 100,
                                   "a factor from 1 to 100");
    if (!(curve.fastMs < curve.slowMs)) {
        fail(source, qualified(section, "fast_ms"),
             "must be below slow_ms (" + numberText(curve.slowMs) + "), got " +
                 numberText(curve.fastMs));
    }
    return curve;
}

EncoderConfig readEncoder(const toml::table& table, const std::string& source,
                          const std::string& section, LineRegistry& lines) {
    checkKeys(table, source, section,
              {"a", "b", "axis", "step", "steps_per_detent", "reverse", "acceleration", "slow_ms",
               "fast_ms", "max_factor"});
    EncoderConfig encoder;
    encoder.lineA = lines.take(table, section, "a");
    encoder.lineB = lines.take(table, section, "b");

    const std::optional<std::string> axis = optionalString(table, source, section, "axis");
    if (!axis) {
        fail(source, qualified(section, "axis"),
             "missing (\"azimuth\", \"elevation\" or \"distance\")");
    }
    if (*axis == "azimuth") {
        encoder.axis = KnobAxis::kAzimuth;
    } else if (*axis == "elevation") {
        encoder.axis = KnobAxis::kElevation;
    } else if (*axis == "distance") {
        encoder.axis = KnobAxis::kDistance;
    } else {
        fail(source, qualified(section, "axis"),
             "expected \"azimuth\", \"elevation\" or \"distance\", got \"" + *axis + "\"");
    }

    const bool metres = encoder.axis == KnobAxis::kDistance;
    const std::optional<double> step = optionalNumber(table, source, section, "step");
    if (!step) {
        fail(source, qualified(section, "step"),
             metres ? "missing (metres per detent, e.g. 0.05)"
                    : "missing (degrees per detent, e.g. 2)");
    }
    const double maxStep = metres ? 10 : 180;
    if (!(*step > 0) || *step > maxStep) {
        fail(source, qualified(section, "step"),
             std::string("expected ") + (metres ? "metres" : "degrees") +
                 " per detent above 0 and at most " + numberText(maxStep) + ", got " +
                 numberText(*step));
    }
    encoder.step = *step;

    if (const auto steps = optionalInteger(table, source, section, "steps_per_detent")) {
        if (*steps != 1 && *steps != 2 && *steps != 4) {
            fail(source, qualified(section, "steps_per_detent"),
                 "expected 1, 2 or 4 (quadrature transitions per click; KY-040: 4), got " +
                     std::to_string(*steps));
        }
        encoder.stepsPerDetent = static_cast<int>(*steps);
    }
    encoder.reverse = optionalBool(table, source, section, "reverse").value_or(false);

    const bool inlineKeys =
        table.contains("slow_ms") || table.contains("fast_ms") || table.contains("max_factor");
    if (const toml::table* acceleration = optionalTable(table, source, section, "acceleration")) {
        if (inlineKeys) {
            fail(source, qualified(section, "acceleration"),
                 "given twice (as a table and as slow_ms/fast_ms/max_factor keys)");
        }
        const std::string sub = qualified(section, "acceleration");
        checkKeys(*acceleration, source, sub, {"slow_ms", "fast_ms", "max_factor"});
        encoder.acceleration = readAcceleration(*acceleration, source, sub);
    } else if (inlineKeys) {
        encoder.acceleration = readAcceleration(table, source, section);
    }
    return encoder;
}

ButtonConfig readButton(const toml::table& table, const std::string& source,
                        const std::string& section, LineRegistry& lines) {
    checkKeys(table, source, section, {"line", "action", "active_low", "debounce_ms"});
    ButtonConfig button;
    button.line = lines.take(table, section, "line");
    const std::optional<std::string> action = optionalString(table, source, section, "action");
    if (!action) {
        fail(source, qualified(section, "action"),
             "missing (\"next-preset\", \"previous-preset\" or \"reset\")");
    }
    if (*action == "next-preset") {
        button.action = ButtonAction::kNextPreset;
    } else if (*action == "previous-preset") {
        button.action = ButtonAction::kPreviousPreset;
    } else if (*action == "reset") {
        button.action = ButtonAction::kReset;
    } else {
        fail(source, qualified(section, "action"),
             "expected \"next-preset\", \"previous-preset\" or \"reset\", got \"" + *action + "\"");
    }
    button.activeLow = optionalBool(table, source, section, "active_low").value_or(true);
    button.debounceMs = readNumberIn(table, source, section, "debounce_ms", button.debounceMs, 0,
                                     1000, "milliseconds from 0 to 1000");
    return button;
}

}  // namespace

KnobsConfig parseKnobsConfig(const toml::table& gpio, const std::string& source) {
    const std::string section = "gpio";
    checkKeys(gpio, source, section, {"enabled", "chip", "consumer", "encoder", "button"});
    KnobsConfig config;
    if (auto chip = optionalString(gpio, source, section, "chip")) {
        if (chip->empty()) {
            fail(source, "gpio.chip", "is empty (a chip such as \"gpiochip0\" or a path)");
        }
        config.chip = *chip;
    }
    if (auto consumer = optionalString(gpio, source, section, "consumer")) {
        if (consumer->empty() || consumer->size() > kMaxConsumerLength) {
            fail(source, "gpio.consumer",
                 "expected 1 to " + std::to_string(kMaxConsumerLength) + " characters, got " +
                     std::to_string(consumer->size()));
        }
        config.consumer = *consumer;
    }

    LineRegistry lines(source);
    const std::vector<const toml::table*> encoders =
        optionalTableArray(gpio, source, section, "encoder");
    for (std::size_t i = 0; i < encoders.size(); ++i) {
        config.encoders.push_back(
            readEncoder(*encoders[i], source, "gpio.encoder[" + std::to_string(i) + "]", lines));
    }
    const std::vector<const toml::table*> buttons =
        optionalTableArray(gpio, source, section, "button");
    for (std::size_t i = 0; i < buttons.size(); ++i) {
        config.buttons.push_back(
            readButton(*buttons[i], source, "gpio.button[" + std::to_string(i) + "]", lines));
    }

    const bool hasLines = !config.encoders.empty() || !config.buttons.empty();
    const std::optional<bool> enabled = optionalBool(gpio, source, section, "enabled");
    if (enabled.value_or(false) && !hasLines) {
        fail(source, "gpio.enabled", "is true but no [[gpio.encoder]] or [[gpio.button]] is given");
    }
    config.enabled = enabled.value_or(hasLines);
    return config;
}

}  // namespace vpe::firmware::knobs
