// SPDX-License-Identifier: MIT
// vpe_player_figures: docs/player.md's two measurements of the real vpe-player, headless, on the
// GLES tests' vase bundle (160 × 120: low resolution), with inputs replayed through the decoders.
//
//   latency  knob detents (4 bouncy edges each) at random phases against the 60 Hz frame
//            timer; input-to-frame latency = the event's timestamp → the frame showing it
//            submitted. Goal: p50 and p99 ≤ one frame period (16.7 ms).
//   soak     N frames (default 100,000) unpaced, a looping replay of knob turns, button
//            presses, OSC messages and camera frames; RSS after the first frame and at the end,
//            errors.
//
// Usage: vpe_player_figures [--bundle PATH] [latency] [soak [FRAMES]]  (both by default;
// --bundle plays PATH, the demo's bundle say, at its projector's size, instead of the vase).
// Prints the player's JSON lines and a summary per figure. Run by hand on an idle machine.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "gles_test_bundle.h"
#include "replay_script.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;

const char* const kBoard = R"([display]
backend = "headless"
[render]
rate = RATE
[light]
azimuth = [-90, 90]
elevation = [0, 80]
[idle]
quiet_s = 2
period_s = 10
)";

std::string run(const std::string& command) {
    std::string output;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) {
        return output;
    }
    char buffer[4096];
    while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) {
        output += buffer;
    }
    const int status = ::pclose(pipe);
    if (status != 0) {
        std::cerr << "vpe_player_figures: vpe-player failed (status " << status << ")\n";
        std::exit(1);
    }
    return output;
}

std::string lastLine(const std::string& text) {
    const std::size_t end = text.find_last_not_of('\n');
    const std::size_t start = text.rfind('\n', end);
    return text.substr(start == std::string::npos ? 0 : start + 1, end - start);
}

double field(const std::string& json, const std::string& path) {
    std::size_t at = 0;
    std::stringstream keys(path);
    std::string key;
    while (std::getline(keys, key, '.')) {
        at = json.find("\"" + key + "\": ", at);
        if (at == std::string::npos) {
            return -1;
        }
        at += key.size() + 4;
    }
    return std::stod(json.substr(at));
}

fs::path writeBoard(const fs::path& folder, const std::string& rate) {
    std::string text = kBoard;
    text.replace(text.find("RATE"), 4, rate);
    text += vpe::testing::replayBoardInputs(false);
    const fs::path path = folder / ("board-" + rate + ".toml");
    std::ofstream(path) << text;
    return path;
}

void latency(const fs::path& folder, const fs::path& bundle) {
    vpe::testing::ReplayScript script;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> phase(0.0, 1.0);
    double t = 0.5;
    int detents = 0;
    for (int i = 0; i < 400; ++i) {
        // A detent every 60–110 ms: its edges fall at every phase of the 16.7 ms frame clock.
        const int direction = (i / 20) % 2 == 0 ? 1 : -1;
        script.knobTurn(17, 18, t, direction, 0.05, 0.001, 1);
        t += 0.06 + 0.05 * phase(random);
        ++detents;
    }
    const fs::path replay = folder / "latency.jsonl";
    script.write(replay);
    const std::string output = run(std::string(vpe::test_paths::playerPath()) + " --board " +
                                   writeBoard(folder, "60").string() + " --bundle " +
                                   bundle.string() + " --replay " + replay.string() + " --json");
    const std::string json = lastLine(output);
    std::cout << json << "\n";
    const double p50 = field(json, "latency_ms.p50"), p99 = field(json, "latency_ms.p99");
    const double period = 1000.0 / 60.0;
    std::printf(
        "latency: %d knob detents at 60 Hz: p50 %.2f ms (%.2f of a frame), p99 %.2f ms "
        "(%.2f of a frame), max %.2f ms; frame p50 %.2f ms\n",
        detents, p50, p50 / period, p99, p99 / period, field(json, "latency_ms.max"),
        field(json, "frame_ms.p50"));
}

void soak(const fs::path& folder, const fs::path& bundle, long frames) {
    vpe::testing::ReplayScript script;
    double t = 0.1;
    for (int round = 0; round < 4; ++round) {
        t = script.knobTurn(17, 18, t, 8, 0.03, 0.002, 2);
        t = script.knobTurn(22, 23, t, -4, 0.03);
        script.buttonPress(27, t, 0.05);
        script.osc(t + 0.1, "/vpe/light/azimuth", std::to_string(10 * round - 20));
        script.osc(t + 0.15, "/vpe/light/position", "0.2, 0.5, 0.4");
        script.osc(t + 0.2, "/vpe/light/azimuth", "999");  // refused, counted
        for (int frame = 0; frame < 30; ++frame) {
            script.cameraLamp(t + 0.3 + frame * 0.02, 60 + 6 * frame, 100 + 2 * frame);
        }
        t += 1.2;
        script.cameraEmpty(t);
        t += 3.0;  // quiet: the drift takes over
    }
    const fs::path replay = folder / "soak.jsonl";
    script.write(replay);
    const std::string output =
        run(std::string(vpe::test_paths::playerPath()) + " --board " +
            writeBoard(folder, "0").string() + " --bundle " + bundle.string() + " --replay " +
            replay.string() + " --replay-loop --frames " + std::to_string(frames) + " --json");
    const std::string json = lastLine(output);
    std::cout << json << "\n";
    std::printf(
        "soak: %.0f frames in %.0f s (%.0f fps, frame p99 %.2f ms), RSS %.0f KiB after the "
        "first frame, %.0f KiB after 1,000 frames, %.0f KiB at the end (%+.0f KiB since "
        "frame 1,000), errors %.0f, events knobs %.0f osc %.0f camera %.0f\n",
        field(json, "frames"), field(json, "seconds"), field(json, "fps"),
        field(json, "frame_ms.p99"), field(json, "rss_kb.start"), field(json, "rss_kb.warm"),
        field(json, "rss_kb.end"), field(json, "rss_kb.end") - field(json, "rss_kb.warm"),
        field(json, "errors"), field(json, "events.knobs"), field(json, "events.osc"),
        field(json, "events.camera"));
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> arguments(argv + 1, argv + argc);
    const fs::path folder =
        fs::temp_directory_path() / ("vpe-player-figures-" + std::to_string(::getpid()));
    fs::create_directories(folder);
    fs::path bundle = folder / "scene.vpeb";
    const auto given = std::find(arguments.begin(), arguments.end(), "--bundle");
    if (given != arguments.end() && given + 1 != arguments.end()) {
        bundle = fs::absolute(*(given + 1));
        arguments.erase(given, given + 2);
    } else {
        const std::vector<std::byte> bytes = vpe::renderer::testing::buildGlesTestBundle();
        std::ofstream(bundle, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()),
                   static_cast<std::streamsize>(bytes.size()));
    }
    const bool all = arguments.empty();
    for (std::size_t i = 0; i < arguments.size() || all; ++i) {
        if (all || arguments[i] == "latency") {
            latency(folder, bundle);
        }
        if (all || arguments[i] == "soak") {
            long frames = 100'000;
            if (!all && i + 1 < arguments.size() &&
                std::isdigit(static_cast<unsigned char>(arguments[i + 1][0]))) {
                frames = std::stol(arguments[++i]);
            }
            soak(folder, bundle, frames);
        }
        if (all) {
            break;
        }
    }
    fs::remove_all(folder);
    return 0;
}
