// SPDX-License-Identifier: MIT
// vpe-player: the device program's frame loop (firmware/README.md). Board file → platform
// (headless EGL or KMS), bundle → GlesFrameRenderer, then N frames under a scripted light
// path, timed; frames optionally written as PPM (headless). Bad input: one line, exit 2.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "vpe/firmware/board_config.h"
#include "vpe/firmware/light_path.h"
#include "vpe/firmware/player_options.h"
#include "vpe/firmware/ppm_writer.h"
#include "vpe/proto/bundle.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"
#include "vpe/renderer/gles/headless_egl_platform.h"
#include "vpe/renderer/gles/kms_platform.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace gles = vpe::renderer::gles;
namespace fw = vpe::firmware;

// Bad input (arguments, board, bundle, display): exit status 2.
struct InputError {
    std::string message;
};

double milliseconds(Clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

// Nearest rank: the smallest value with at least q of the samples at or below it.
double percentile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
    return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
            out += escaped;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

// The renderer's errors name the bundle already; others get its name in front.
std::string namingBundle(const std::filesystem::path& bundle, const std::string& message) {
    return message.rfind(bundle.string() + ":", 0) == 0 ? message
                                                        : bundle.string() + ": " + message;
}

std::unique_ptr<gles::GraphicsPlatform> createPlatform(const fw::BoardConfig& board) {
    try {
        if (board.display.backend == fw::DisplayBackend::kHeadless) {
            return gles::createHeadlessEglPlatform();
        }
        gles::KmsOptions kms;
        kms.device = board.display.device;
        kms.connector = board.display.connector;
        kms.atomic = board.display.atomic;
        if (board.display.mode) {
            kms.modeWidth = board.display.mode->width;
            kms.modeHeight = board.display.mode->height;
            kms.modeRefresh = board.display.mode->refresh;
        }
        return gles::createKmsPlatform(kms);
    } catch (const gles::GraphicsError& error) {
        throw InputError{error.what()};
    }
}

int run(const fw::PlayerOptions& options, Clock::time_point start) {
    fw::BoardConfig board;
    try {
        board = fw::loadBoardConfig(options.board);
    } catch (const fw::BoardConfigError& error) {
        throw InputError{error.what()};
    }
    const bool headless = board.display.backend == fw::DisplayBackend::kHeadless;
    if (options.out && !headless) {
        throw InputError{"--out: frames are read back only on the headless display (" +
                         options.board.string() + " uses kms)"};
    }
    std::optional<vpe::proto::BundleFile> bundle;
    try {
        bundle.emplace(vpe::proto::BundleFile::open(options.bundle));
    } catch (const vpe::proto::BundleError& error) {
        throw InputError{error.what()};
    }
    const vpe::proto::BundleView& view = bundle->view();

    std::unique_ptr<gles::GraphicsPlatform> platform = createPlatform(board);
    std::unique_ptr<gles::GlesFrameRenderer> renderer;
    try {
        renderer = std::make_unique<gles::GlesFrameRenderer>(view);
        renderer->selectPreset(options.preset);
    } catch (const gles::GraphicsError& error) {
        throw InputError{namingBundle(options.bundle, error.what())};
    } catch (const std::invalid_argument& error) {
        throw InputError{namingBundle(options.bundle, error.what())};
    }
    // The renderer draws the projector's frame at its calibrated size: the target must match.
    int width = renderer->width(), height = renderer->height();
    if (options.width) {
        width = *options.width;
        height = *options.height;
    } else if (headless && board.render.width) {
        width = *board.render.width;
        height = *board.render.height;
    }
    if (width != renderer->width() || height != renderer->height()) {
        throw InputError{
            (options.width ? std::string("--size") : options.board.string() + ":render.size") +
            ": " + std::to_string(width) + "x" + std::to_string(height) +
            " differs from the bundle's projector " + std::to_string(renderer->width()) + "x" +
            std::to_string(renderer->height())};
    }
    std::unique_ptr<gles::RenderTarget> target;
    try {
        target = platform->createRenderTarget(width, height);
    } catch (const gles::GraphicsError& error) {
        throw InputError{error.what()};
    }
    if (options.out) {
        std::error_code error;
        std::filesystem::create_directories(*options.out, error);
        if (error || !std::filesystem::is_directory(*options.out)) {
            throw InputError{options.out->string() + ": cannot create the output folder (" +
                             (error ? error.message() : "not a folder") + ")"};
        }
    }

    const vpe::proto::RenderSettings& settings = view.settings();
    const fw::ScriptedLightPath path(view.mesh().positions, settings.viewerPosition);
    gles::FrameInputs inputs;
    inputs.viewerPosition = settings.viewerPosition;
    inputs.gain = settings.gain;
    std::vector<double> frameMs;
    frameMs.reserve(static_cast<std::size_t>(options.frames));
    double firstFrameMs = 0;
    long written = 0;
    for (long frame = 0; frame < options.frames; ++frame) {
        inputs.lightPosition = path.position(frame);
        const Clock::time_point begin = Clock::now();
        renderer->render(*target, inputs);
        target->present();  // headless: glFinish; KMS: swap + page flip, waits for vsync
        std::vector<std::uint8_t> rgba;
        if (headless) {
            rgba = target->readRgba8();  // the frame leaves the GPU, as a scanout would
        }
        const Clock::time_point end = Clock::now();
        frameMs.push_back(milliseconds(end - begin));
        if (frame == 0) {
            firstFrameMs = milliseconds(end - start);
        }
        if (options.out && frame % options.every == 0) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%05ld.ppm", frame);
            fw::writePpmAtomically(*options.out / name, width, height, rgba);
            ++written;
        }
    }

    double total = 0;
    for (const double ms : frameMs) {
        total += ms;
    }
    const double mean = total / static_cast<double>(frameMs.size());
    const double fps = 1000.0 / mean;
    const double p50 = percentile(frameMs, 0.5), p99 = percentile(frameMs, 0.99);
    const double worst = *std::max_element(frameMs.begin(), frameMs.end());
    std::cout << "vpe-player: " << options.frames << " frames " << width << "x" << height
              << ", preset '" << renderer->presetName() << "', on " << platform->description()
              << ": " << fps << " fps, frame p50 " << p50 << " ms, p99 " << p99
              << " ms; first frame " << firstFrameMs << " ms after start";
    if (options.out) {
        std::cout << "; " << written << " frames in " << options.out->string();
    }
    std::cout << "\n";
    if (options.json) {
        std::ostringstream json;
        json << "{\"frames\": " << options.frames << ", \"width\": " << width
             << ", \"height\": " << height << ", \"preset\": " << jsonString(renderer->presetName())
             << ", \"platform\": " << jsonString(platform->description()) << ", \"fps\": " << fps
             << ", \"frame_ms\": {\"p50\": " << p50 << ", \"p99\": " << p99
             << ", \"mean\": " << mean << ", \"max\": " << worst
             << "}, \"first_frame_ms\": " << firstFrameMs << ", \"written\": " << written << "}\n";
        std::cout << json.str();
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Clock::time_point start = Clock::now();
    try {
        const fw::PlayerOptions options =
            fw::parsePlayerOptions(std::vector<std::string>(argv + 1, argv + argc));
        if (options.help) {
            std::cout << fw::playerUsage();
            return 0;
        }
        return run(options, start);
    } catch (const fw::PlayerUsageError& error) {
        std::cerr << "vpe-player: " << error.what() << "\n";
        return 2;
    } catch (const InputError& error) {
        std::cerr << "vpe-player: " << error.message << "\n";
        return 2;
    } catch (const std::exception& error) {
        std::cerr << "vpe-player: " << error.what() << "\n";
        return 1;
    }
}
