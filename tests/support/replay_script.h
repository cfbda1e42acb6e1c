// SPDX-License-Identifier: MIT
// ReplayScript: writes `vpe-player --replay` files (firmware/README.md) for tests and the
// player's latency and soak benchmarks: knob detents as the four GPIO edges a KY-040 makes
// (optionally with contact bounce), button presses, OSC messages and camera frames.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace vpe::testing {

// The board sections ReplayScript's files are written for: knobs on lines 17/18 (azimuth, 2° a
// detent) and 22/23 (elevation, 1°), a next-preset button on 27, a calibrated 320 × 240 camera
// (the image centre is azimuth 0, elevation 30). `enabled` switches the hardware on: a replay
// decodes with these settings either way. Ends inside [camera]: add keys, or start a section.
inline std::string replayBoardInputs(bool enabled, const std::string& chip = "gpiochip9") {
    const std::string on = enabled ? "true" : "false";
    return "[gpio]\nenabled = " + on + "\nchip = \"" + chip +
           "\"\n"
           "[[gpio.encoder]]\na = 17\nb = 18\naxis = \"azimuth\"\nstep = 2\n"
           "[[gpio.encoder]]\na = 22\nb = 23\naxis = \"elevation\"\nstep = 1\n"
           "[[gpio.button]]\nline = 27\naction = \"next-preset\"\n"
           "[camera]\nenabled = " +
           on +
           "\nsize = \"320x240\"\nhold_s = 0.3\n"
           "calibration = [[10, 230, -60, 0], [310, 230, 60, 0], [10, 10, -60, 60], "
           "[310, 10, 60, 60]]\n";
}

class ReplayScript {
public:
    // `detents` clicks (sign: + clockwise) on the encoder wired to lines a and b, from
    // `start` seconds, one every `spacing` s; the four edges of a click `edgeGap` s apart.
    // With bounce, each edge is preceded by an even number of extra toggles of its line.
    double knobTurn(unsigned a, unsigned b, double start, int detents, double spacing,
                    double edgeGap = 0.002, int bounce = 0) {
        double t = start;
        for (int i = 0; i < std::abs(detents); ++i) {
            // Clockwise (A leads): A falls, B falls, A rises, B rises.
            const unsigned first = detents > 0 ? a : b, second = detents > 0 ? b : a;
            const unsigned lines[4] = {first, second, first, second};
            const bool rising[4] = {false, false, true, true};
            for (int e = 0; e < 4; ++e) {
                for (int k = 0; k < bounce; ++k) {  // chatter: leave and come back
                    edge(t, lines[e], !rising[e] ? false : true);
                    t += edgeGap / (4.0 * (bounce + 1));
                    edge(t, lines[e], !rising[e] ? true : false);
                    t += edgeGap / (4.0 * (bounce + 1));
                }
                edge(t, lines[e], rising[e]);
                t += edgeGap;
            }
            t = start + spacing * (i + 1);
        }
        return t;
    }

    // A press of an active-low button held for `hold` s.
    void buttonPress(unsigned line, double at, double hold) {
        edge(at, line, false);
        edge(at + hold, line, true);
    }

    // args: the JSON array's inside, e.g. "30.5" or "1, 2, 3".
    void osc(double at, const std::string& path, const std::string& args = "") {
        line("{\"t\": " + seconds(at) + ", \"type\": \"osc\", \"path\": \"" + path +
             "\", \"args\": [" + args + "]}");
    }

    void cameraLamp(double at, double x, double y, double radius = 4) {
        line("{\"t\": " + seconds(at) + ", \"type\": \"camera\", \"x\": " + seconds(x) +
             ", \"y\": " + seconds(y) + ", \"radius\": " + seconds(radius) + "}");
    }
    void cameraEmpty(double at) { line("{\"t\": " + seconds(at) + ", \"type\": \"camera\"}"); }

    const std::string& text() const { return text_; }
    void write(const std::filesystem::path& path) const {
        std::ofstream(path, std::ios::binary) << text_;
    }

private:
    void edge(double at, unsigned lineOffset, bool isRising) {
        line("{\"t\": " + seconds(at) +
             ", \"type\": \"gpio\", \"line\": " + std::to_string(lineOffset) + ", \"edge\": \"" +
             (isRising ? "rising" : "falling") + "\"}");
    }
    static std::string seconds(double value) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9f", value);
        return text;
    }
    void line(const std::string& json) { text_ += json + "\n"; }

    std::string text_;
};

}  // namespace vpe::testing
