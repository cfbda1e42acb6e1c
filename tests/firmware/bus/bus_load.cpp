// SPDX-License-Identifier: MIT
// vpe_bus_load: a controller that publishes light states far faster than any person steers, to
// show that the nodes keep their frame rate and their memory flat under it
// (scripts/multi-node-report.sh). Valid states (format 1), retained, QoS 0, each the newest: an
// azimuth sweeping ±30° every 4 s at elevation 30°, no move and no drift, so a node shows
// exactly the newest it read. Paced by an absolute clock; reports what it sent as one JSON line.
//   vpe_bus_load --port P --user U --password W --show S [--host 127.0.0.1] [--rate 1000]
//                [--seconds 60] [--distance 0.6] [--client-id vpe-load]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "vpe/firmware/bus/light_message.h"
#include "vpe/firmware/bus/mqtt_connection.h"
#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/loop/show_clock.h"

namespace {

namespace bus = vpe::firmware::bus;

[[noreturn]] void usage(const std::string& problem) {
    std::cerr << "vpe_bus_load: " << problem
              << " (usage: --port P --user U --password W --show S [--host H] [--rate N] "
                 "[--seconds T] [--distance M] [--client-id ID])\n";
    std::exit(2);
}

double number(const std::string& option, const std::string& text, double low, double high) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(value >= low && value <= high)) {
        usage(option + ": expected a number in [" + std::to_string(low) + ", " +
              std::to_string(high) + "], got \"" + text + "\"");
    }
    return value;
}

}  // namespace

int main(int argc, char** argv) {
    bus::MqttSettings settings;
    settings.clientId = "vpe-load";
    std::string show;
    double rate = 1000, seconds = 60, distance = 0.6;
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    for (std::size_t i = 0; i < arguments.size(); i += 2) {
        if (i + 1 >= arguments.size()) {
            usage(arguments[i] + ": missing value");
        }
        const std::string& option = arguments[i];
        const std::string& value = arguments[i + 1];
        if (option == "--port") {
            settings.port = static_cast<int>(number(option, value, 1, 65535));
        } else if (option == "--host") {
            settings.host = value;
        } else if (option == "--user") {
            settings.username = value;
        } else if (option == "--password") {
            settings.password = value;
        } else if (option == "--show") {
            show = value;
        } else if (option == "--rate") {
            rate = number(option, value, 1, 100000);
        } else if (option == "--seconds") {
            seconds = number(option, value, 0.1, 3600);
        } else if (option == "--distance") {
            distance = number(option, value, 0.001, 100);
        } else if (option == "--client-id") {
            settings.clientId = value;
        } else {
            usage(option + ": unknown argument");
        }
    }
    if (show.empty()) {
        usage("--show: missing");
    }
    const std::string topic = "vpe/" + show + "/light";
    std::string problem;
    bus::MqttConnection::Handlers handlers;
    handlers.refused = [&](int, const std::string& reason) { problem = reason; };
    handlers.lost = [&](const std::string& reason, bool) { problem = reason; };
    bus::MqttConnection connection(settings, handlers);

    // Connect first (up to 5 s), then publish on an absolute schedule.
    const std::int64_t start = vpe::firmware::monotonicNowNs();
    while (!connection.connected() && vpe::firmware::monotonicNowNs() - start < 5'000'000'000) {
        connection.service(vpe::firmware::monotonicNowNs());
        timespec nap{0, 1'000'000};
        ::nanosleep(&nap, nullptr);
    }
    if (!connection.connected()) {
        std::cerr << "vpe_bus_load: " << connection.endpoint() << ": cannot connect ("
                  << (problem.empty() ? "no answer" : problem) << ")\n";
        return 1;
    }
    const auto periodNs = static_cast<std::int64_t>(1e9 / rate);
    const auto count = static_cast<std::uint64_t>(std::llround(rate * seconds));
    const std::int64_t began = vpe::firmware::monotonicNowNs();
    std::uint64_t sent = 0, failed = 0;
    bus::LightMessage message;
    message.node = settings.clientId;
    message.source = "osc";
    for (std::uint64_t k = 0; k < count; ++k) {
        const std::int64_t due = began + static_cast<std::int64_t>(k) * periodNs;
        timespec at{static_cast<time_t>(due / 1'000'000'000),
                    static_cast<long>(due % 1'000'000'000)};
        ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr);
        const std::int64_t nowUs = vpe::firmware::realtimeNowNs() / 1000;
        const double phase = 2.0 * std::numbers::pi * static_cast<double>(k) / (4.0 * rate);
        message.seq = k + 1;
        message.timeUs = nowUs;
        message.fromUs = nowUs;
        message.target = {30.0 * std::sin(phase), 30.0, distance};
        message.from = message.target;
        if (connection.publish(topic, bus::encodeLightMessage(message), 0, true)) {
            ++sent;
        } else {
            ++failed;
        }
        connection.service(vpe::firmware::monotonicNowNs());
    }
    const double took = static_cast<double>(vpe::firmware::monotonicNowNs() - began) * 1e-9;
    std::printf("{\"sent\": %llu, \"failed\": %llu, \"seconds\": %.3f, \"rate\": %.1f}\n",
                static_cast<unsigned long long>(sent), static_cast<unsigned long long>(failed),
                took, static_cast<double>(sent) / took);
    return failed == 0 ? 0 : 1;
}
