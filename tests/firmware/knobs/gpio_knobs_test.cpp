// SPDX-License-Identifier: MIT
// GpioKnobs without hardware: a missing or wrong GPIO chip is a KnobsUnavailable of one line
// naming the chip and what is wrong. On a board that has the chip, the test that needs it
// absent reports SKIP.
#include "vpe/firmware/knobs/gpio_knobs.h"

#include <filesystem>

#include <gtest/gtest.h>

namespace vpe::firmware::knobs {
namespace {

KnobsConfig oneKnobOn(const std::string& chip) {
    KnobsConfig config;
    config.enabled = true;
    config.chip = chip;
    config.encoders.push_back(EncoderConfig{17, 27, KnobAxis::kAzimuth, 2, 4, false, {}});
    config.buttons.push_back(ButtonConfig{22, ButtonAction::kReset, true, 20});
    return config;
}

std::string errorOf(const KnobsConfig& config) {
    try {
        GpioKnobs knobs(config);
    } catch (const KnobsUnavailable& error) {
        const std::string message = error.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
    return "(no error)";
}

TEST(GpioKnobsTest, AMissingChipIsOneLineNamingIt) {
    if (std::filesystem::exists("/dev/gpiochip0")) {
        GTEST_SKIP() << "/dev/gpiochip0 exists on this machine";
    }
    EXPECT_EQ(errorOf(oneKnobOn("gpiochip0")),
              "gpiochip0: cannot open GPIO chip (No such file or directory)");
}

TEST(GpioKnobsTest, AMissingPathIsOneLineNamingIt) {
    EXPECT_EQ(errorOf(oneKnobOn("/dev/vpe-no-such-gpiochip")),
              "/dev/vpe-no-such-gpiochip: cannot open GPIO chip (No such file or directory)");
}

TEST(GpioKnobsTest, ANodeThatIsNoGpioChipIsRefused) {
    const std::string message = errorOf(oneKnobOn("/dev/null"));
    EXPECT_EQ(message.rfind("/dev/null: cannot open GPIO chip (not a GPIO chip: ", 0), 0U)
        << message;
}

TEST(GpioKnobsTest, NothingToReadIsRefused) {
    KnobsConfig config;
    EXPECT_EQ(errorOf(config), "gpiochip0: no [[gpio.encoder]] or [[gpio.button]] lines to read");
}

}  // namespace
}  // namespace vpe::firmware::knobs
