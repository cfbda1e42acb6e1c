// SPDX-License-Identifier: MIT
// parseKnobsConfig: a full [gpio] section, defaults, and one-line errors naming
// file:gpio.encoder[i].key for every kind of bad value.
#include "vpe/firmware/knobs/knobs_config.h"

#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "vpe/firmware/board/board_config.h"

#include "test_paths.h"

namespace vpe::firmware::knobs {
namespace {

KnobsConfig parseGpio(const std::string& text) {
    const toml::table root = toml::parse(text, std::string_view("board.toml"));
    const toml::table* gpio = root["gpio"].as_table();
    return parseKnobsConfig(gpio != nullptr ? *gpio : toml::table{}, "board.toml");
}

std::string errorOf(const std::string& text) {
    try {
        parseGpio(text);
    } catch (const BoardConfigError& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
    return "(no error)";
}

// Each text refused with exactly its one line.
void expectRefusals(const std::vector<std::pair<std::string, std::string>>& refusals) {
    for (const auto& [text, refusal] : refusals) {
        EXPECT_EQ(errorOf(text), refusal) << text;
    }
}

const char* const kEncoder = "[[gpio.encoder]]\na = 17\nb = 27\naxis = \"azimuth\"\nstep = 2\n";

TEST(KnobsConfigTest, ReadsAFullSection) {
    const KnobsConfig config = parseGpio(R"(
[gpio]
chip = "/dev/gpiochip4"
consumer = "vpe-knobs"

[[gpio.encoder]]
a = 17
b = 27
axis = "azimuth"
step = 2.5
acceleration = { slow_ms = 150, fast_ms = 25, max_factor = 6 }

[[gpio.encoder]]
a = 5
b = 6
axis = "distance"
step = 0.05
steps_per_detent = 2
reverse = true
max_factor = 3

[[gpio.encoder]]
a = 12
b = 13
axis = "elevation"
step = 1

[gpio.encoder.acceleration]
fast_ms = 10

[[gpio.button]]
line = 22
action = "next-preset"

[[gpio.button]]
line = 23
action = "previous-preset"
active_low = false
debounce_ms = 35

[[gpio.button]]
line = 24
action = "reset"
)");
    EXPECT_TRUE(config.enabled);
    EXPECT_EQ(config.chip, "/dev/gpiochip4");
    EXPECT_EQ(config.consumer, "vpe-knobs");
    ASSERT_EQ(config.encoders.size(), 3U);
    const EncoderConfig& azimuth = config.encoders[0];
    EXPECT_EQ(azimuth.lineA, 17U);
    EXPECT_EQ(azimuth.lineB, 27U);
    EXPECT_EQ(azimuth.axis, KnobAxis::kAzimuth);
    EXPECT_EQ(azimuth.step, 2.5);
    EXPECT_EQ(azimuth.stepsPerDetent, 4);
    EXPECT_FALSE(azimuth.reverse);
    EXPECT_EQ(azimuth.acceleration.slowMs, 150);
    EXPECT_EQ(azimuth.acceleration.fastMs, 25);
    EXPECT_EQ(azimuth.acceleration.maxFactor, 6);
    const EncoderConfig& distance = config.encoders[1];
    EXPECT_EQ(distance.axis, KnobAxis::kDistance);
    EXPECT_EQ(distance.stepsPerDetent, 2);
    EXPECT_TRUE(distance.reverse);
    EXPECT_EQ(distance.acceleration.maxFactor, 3);  // inline keys
    EXPECT_EQ(distance.acceleration.slowMs, 120);   // defaults for the rest
    EXPECT_EQ(distance.acceleration.fastMs, 30);
    const EncoderConfig& elevation = config.encoders[2];
    EXPECT_EQ(elevation.axis, KnobAxis::kElevation);
    EXPECT_EQ(elevation.acceleration.fastMs, 10);  // a sub-table, written out
    EXPECT_EQ(elevation.acceleration.maxFactor, 4);
    ASSERT_EQ(config.buttons.size(), 3U);
    EXPECT_EQ(config.buttons[0].line, 22U);
    EXPECT_EQ(config.buttons[0].action, ButtonAction::kNextPreset);
    EXPECT_TRUE(config.buttons[0].activeLow);
    EXPECT_EQ(config.buttons[0].debounceMs, 20);
    EXPECT_EQ(config.buttons[1].action, ButtonAction::kPreviousPreset);
    EXPECT_FALSE(config.buttons[1].activeLow);
    EXPECT_EQ(config.buttons[1].debounceMs, 35);
    EXPECT_EQ(config.buttons[2].action, ButtonAction::kReset);
    EXPECT_STREQ(knobAxisName(elevation.axis), "elevation");
    EXPECT_STREQ(buttonActionName(config.buttons[1].action), "previous-preset");
}

TEST(KnobsConfigTest, DefaultsAndEnabled) {
    const KnobsConfig empty = parseGpio("[gpio]\n");
    EXPECT_FALSE(empty.enabled);  // nothing to read
    EXPECT_EQ(empty.chip, "gpiochip0");
    EXPECT_EQ(empty.consumer, "vpe-player");
    EXPECT_TRUE(empty.encoders.empty());

    const KnobsConfig one = parseGpio(kEncoder);
    EXPECT_TRUE(one.enabled);
    EXPECT_EQ(one.encoders[0].acceleration.maxFactor, 1);  // no acceleration unless asked

    const KnobsConfig off = parseGpio(std::string("[gpio]\nenabled = false\n") + kEncoder);
    EXPECT_FALSE(off.enabled);
    EXPECT_EQ(off.encoders.size(), 1U);  // still read and checked
}

TEST(KnobsConfigTest, TheRepositoryBoardsSectionsParse) {
    for (const char* board : {"/boards/rpi4.toml", "/boards/rpi5.toml", "/boards/headless.toml"}) {
        SCOPED_TRACE(board);
        const toml::table root = toml::parse_file(std::string(test_paths::sourceDir()) + board);
        if (const toml::table* gpio = root["gpio"].as_table()) {
            EXPECT_NO_THROW(parseKnobsConfig(*gpio, board));
        }
    }
}

TEST(KnobsConfigTest, RefusesBadSectionsWithOneLine) {
    const std::string e = kEncoder;
    expectRefusals({
        {"[gpio]\npins = 3\n",
         "board.toml:gpio.pins: unknown key (known: button, chip, consumer, enabled, "
         "encoder)"},
        {"[gpio]\nenabled = 1\n", "board.toml:gpio.enabled: expected a boolean, got an integer"},
        {"[gpio]\nenabled = true\n",
         "board.toml:gpio.enabled: is true but no [[gpio.encoder]] or [[gpio.button]] is "
         "given"},
        {"[gpio]\nchip = \"\"\n",
         "board.toml:gpio.chip: is empty (a chip such as \"gpiochip0\" or a path)"},
        {"[gpio]\nconsumer = \"a-label-far-too-long-for-the-kernel\"\n",
         "board.toml:gpio.consumer: expected 1 to 31 characters, got 35"},
        {"[gpio]\nencoder = 3\n",
         "board.toml:gpio.encoder: expected an array of tables ([[gpio.encoder]]), got an "
         "integer"},
    });

    // Encoders: the index names which one.
    expectRefusals({
        {e + "[[gpio.encoder]]\na = 5\nb = 6\naxis = \"roll\"\nstep = 1\n",
         "board.toml:gpio.encoder[1].axis: expected \"azimuth\", \"elevation\" or "
         "\"distance\", got \"roll\""},
        {"[[gpio.encoder]]\na = 5\nb = 6\nstep = 1\n",
         "board.toml:gpio.encoder[0].axis: missing (\"azimuth\", \"elevation\" or "
         "\"distance\")"},
        {"[[gpio.encoder]]\na = 5\nb = 6\naxis = \"azimuth\"\nstep = 0\n",
         "board.toml:gpio.encoder[0].step: expected degrees per detent above 0 and at most "
         "180, got 0"},
        {"[[gpio.encoder]]\na = 5\nb = 6\naxis = \"distance\"\nstep = -0.1\n",
         "board.toml:gpio.encoder[0].step: expected metres per detent above 0 and at most "
         "10, got -0.1"},
        {"[[gpio.encoder]]\na = 5\nb = 6\naxis = \"azimuth\"\n",
         "board.toml:gpio.encoder[0].step: missing (degrees per detent, e.g. 2)"},
        {"[[gpio.encoder]]\na = 5\nb = 6\naxis = \"azimuth\"\nstep = \"2\"\n",
         "board.toml:gpio.encoder[0].step: expected a number, got a string"},
        {"[[gpio.encoder]]\nb = 6\naxis = \"azimuth\"\nstep = 1\n",
         "board.toml:gpio.encoder[0].a: missing (a line offset on the chip, e.g. 17 for "
         "GPIO17)"},
        {"[[gpio.encoder]]\na = -1\nb = 6\naxis = \"azimuth\"\nstep = 1\n",
         "board.toml:gpio.encoder[0].a: expected a line offset from 0 to 65535, got -1"},
        {"[[gpio.encoder]]\na = 1.5\nb = 6\naxis = \"azimuth\"\nstep = 1\n",
         "board.toml:gpio.encoder[0].a: expected an integer, got a number"},
        {e + "steps_per_detent = 3\n",
         "board.toml:gpio.encoder[0].steps_per_detent: expected 1, 2 or 4 (quadrature "
         "transitions per click; KY-040: 4), got 3"},
        {e + "reverse = \"yes\"\n",
         "board.toml:gpio.encoder[0].reverse: expected a boolean, got a string"},
        {e + "speed = 2\n",
         "board.toml:gpio.encoder[0].speed: unknown key (known: a, acceleration, axis, b, "
         "fast_ms, max_factor, reverse, slow_ms, step, steps_per_detent)"},
        {e + "acceleration = { slow_ms = 20, fast_ms = 40 }\n",
         "board.toml:gpio.encoder[0].acceleration.fast_ms: must be below slow_ms (20), got "
         "40"},
        {e + "acceleration = { max_factor = 0.5 }\n",
         "board.toml:gpio.encoder[0].acceleration.max_factor: expected a factor from 1 to "
         "100, got 0.5"},
        {e + "acceleration = { gain = 2 }\n",
         "board.toml:gpio.encoder[0].acceleration.gain: unknown key (known: fast_ms, "
         "max_factor, slow_ms)"},
        {e + "acceleration = 2\n",
         "board.toml:gpio.encoder[0].acceleration: expected a table, got an integer"},
        {e + "max_factor = 2\nacceleration = { slow_ms = 90 }\n",
         "board.toml:gpio.encoder[0].acceleration: given twice (as a table and as "
         "slow_ms/fast_ms/max_factor keys)"},
        {e + "slow_ms = -5\n",
         "board.toml:gpio.encoder[0].slow_ms: expected milliseconds from 0 to 10000, got -5"},
    });

    // Lines used twice, anywhere in the section.
    expectRefusals({
        {"[[gpio.encoder]]\na = 5\nb = 5\naxis = \"azimuth\"\nstep = 1\n",
         "board.toml:gpio.encoder[0].b: line 5 is already used by gpio.encoder[0].a"},
        {e + "[[gpio.encoder]]\na = 4\nb = 17\naxis = \"elevation\"\nstep = 1\n",
         "board.toml:gpio.encoder[1].b: line 17 is already used by gpio.encoder[0].a"},
        {e + "[[gpio.button]]\nline = 27\naction = \"reset\"\n",
         "board.toml:gpio.button[0].line: line 27 is already used by gpio.encoder[0].b"},
    });

    // Buttons.
    expectRefusals({
        {"[[gpio.button]]\nline = 22\naction = \"next\"\n",
         "board.toml:gpio.button[0].action: expected \"next-preset\", \"previous-preset\" "
         "or \"reset\", got \"next\""},
        {"[[gpio.button]]\nline = 22\n",
         "board.toml:gpio.button[0].action: missing (\"next-preset\", \"previous-preset\" "
         "or \"reset\")"},
        {"[[gpio.button]]\nline = 22\naction = \"reset\"\ndebounce_ms = -1\n",
         "board.toml:gpio.button[0].debounce_ms: expected milliseconds from 0 to 1000, got "
         "-1"},
        {"[[gpio.button]]\nline = 22\naction = \"reset\"\nactive_low = 0\n",
         "board.toml:gpio.button[0].active_low: expected a boolean, got an integer"},
        {"[[gpio.button]]\npin = 22\naction = \"reset\"\n",
         "board.toml:gpio.button[0].pin: unknown key (known: action, active_low, "
         "debounce_ms, line)"},
    });
}

}  // namespace
}  // namespace vpe::firmware::knobs
