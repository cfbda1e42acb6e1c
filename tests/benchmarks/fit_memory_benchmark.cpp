// SPDX-License-Identifier: MIT
// `vpe fit` end to end on the paper's capture size, as users run it: 330 images of
// 2048 × 2048 (8-bit sRGB JPEG, a normal map beside them). The capture is rendered once into
// a cache folder; `vpe fit` then runs as a child process `--runs` times (default 3) and the
// benchmark reports, per run and as medians, the wall time, the command's own phases (decode,
// normals, fit, write), its peak RSS (from wait4) and the model file's size. Extra arguments
// after `--` go to `vpe fit` (e.g. -- --storage float); `--vpe PATH` times another build.
//   vpe_fit_memory_benchmark [--size N] [--dir DIR] [--runs 3] [--vpe PATH] [-- FIT OPTIONS]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "vpe/common/parallel_for.h"
#include "vpe/proto/srgb.h"

#include "command_runs.h"
#include "paper_rig.h"
#include "test_paths.h"

namespace vpe {
namespace {

// A glazed, rippled surface: normals from a height field, albedo streaks, a specular lobe.
proto::Vec3d surfaceNormal(int x, int y, int size) {
    const double u = 12.0 * M_PI * x / size, v = 9.0 * M_PI * y / size;
    const double dx = 0.25 * std::cos(u) * std::cos(0.5 * v);
    const double dy = -0.125 * std::sin(u) * std::sin(0.5 * v) + 0.15 * std::cos(v);
    return proto::normalized(proto::Vec3d{-dx, -dy, 1.0});
}

void writeCapture(const std::filesystem::path& dir, int size) {
    std::filesystem::create_directories(dir);
    const std::vector<proto::Vec3d> lights = benchmarks::paperRigLights();
    std::vector<float> normals(static_cast<std::size_t>(size) * size * 3);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const proto::Vec3d n = surfaceNormal(x, y, size);
            float* out = &normals[(static_cast<std::size_t>(y) * size + x) * 3];
            out[0] = static_cast<float>((n.x + 1) / 2);
            out[1] = static_cast<float>((n.y + 1) / 2);
            out[2] = static_cast<float>((n.z + 1) / 2);
        }
    }
    auto normalOut = OIIO::ImageOutput::create("png");
    normalOut->open((dir / "normals.png").string(),
                    OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::UINT16));
    normalOut->write_image(OIIO::TypeDesc::FLOAT, normals.data());
    normalOut->close();
    std::ofstream lp(dir / "dirs.lp");
    lp << lights.size() << "\n";
    for (std::size_t i = 0; i < lights.size(); ++i) {
        lp << "image" << i << ".jpg " << lights[i].x << " " << lights[i].y << " " << lights[i].z
           << "\n";
    }
    common::parallelFor(
        lights.size(), 1, common::resolveThreadCount(0), [&](std::size_t begin, std::size_t end) {
            std::vector<std::uint8_t> pixels(static_cast<std::size_t>(size) * size * 3);
            for (std::size_t i = begin; i < end; ++i) {
                const proto::Vec3d l = lights[i];
                for (int y = 0; y < size; ++y) {
                    for (int x = 0; x < size; ++x) {
                        const proto::Vec3d n = surfaceNormal(x, y, size);
                        const double nl = std::max(0.0, proto::dot(n, l));
                        const proto::Vec3d h = proto::normalized(proto::Vec3d{l.x, l.y, l.z + 1.0});
                        const double specular =
                            0.4 * std::pow(std::max(0.0, proto::dot(n, h)), 40.0);
                        const double streak = 0.5 + 0.5 * std::sin(0.01 * (x + 2 * y));
                        const double albedo[3] = {0.35 + 0.3 * streak, 0.25 + 0.1 * streak, 0.2};
                        for (int c = 0; c < 3; ++c) {
                            const double linear =
                                std::min(1.0, albedo[c] * nl + specular * nl + 0.01);
                            pixels[(static_cast<std::size_t>(y) * size + x) * 3 + c] =
                                static_cast<std::uint8_t>(
                                    std::lround(proto::linearToSrgb(linear) * 255));
                        }
                    }
                }
                auto out = OIIO::ImageOutput::create("jpg");
                OIIO::ImageSpec spec(size, size, 3, OIIO::TypeDesc::UINT8);
                spec.attribute("CompressionQuality", 92);
                const std::string name = (dir / ("image" + std::to_string(i) + ".jpg")).string();
                if (!out || !out->open(name, spec) ||
                    !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close()) {
                    throw std::runtime_error("cannot write " + name);
                }
            }
        });
}

}  // namespace
}  // namespace vpe

int main(int argc, char** argv) {
    int size = 2048;
    int runs = 3;
    std::filesystem::path dir;
    std::string vpe = vpe::test_paths::vpeExecutablePath();
    std::vector<std::string> fitOptions;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--") == 0) {
            fitOptions.assign(argv + i + 1, argv + argc);
            break;
        }
        if (i + 1 >= argc) {
            break;
        }
        if (std::strcmp(argv[i], "--size") == 0) {
            size = std::atoi(argv[++i]);
        } else if (std::strcmp(argv[i], "--dir") == 0) {
            dir = argv[++i];
        } else if (std::strcmp(argv[i], "--runs") == 0) {
            runs = std::max(1, std::atoi(argv[++i]));
        } else if (std::strcmp(argv[i], "--vpe") == 0) {
            vpe = argv[++i];
        }
    }
    if (dir.empty()) {
        dir =
            std::filesystem::temp_directory_path() / ("vpe-fit-memory-330x" + std::to_string(size));
    }
    using Clock = std::chrono::steady_clock;
    if (!std::filesystem::exists(dir / "dirs.lp")) {
        std::fprintf(stderr, "rendering 330 images of %dx%d into %s ...\n", size, size,
                     dir.c_str());
        const auto start = Clock::now();
        vpe::writeCapture(dir, size);
        std::fprintf(stderr, "rendered in %.1f s\n",
                     std::chrono::duration<double>(Clock::now() - start).count());
    }
    const std::string model = (dir / "model.exr").string();
    std::vector<std::string> arguments{vpe, "fit", dir.string(), "--out", model, "--json"};
    arguments.insert(arguments.end(), fitOptions.begin(), fitOptions.end());
    const char* const phases[] = {"decode", "normals", "fit", "write"};
    std::vector<double> totals, rss, bytes, phaseSeconds[4];
    try {
        for (int run = 0; run < runs; ++run) {
            const vpe::benchmarks::CommandRun result = vpe::benchmarks::runCommand(arguments);
            totals.push_back(result.seconds);
            rss.push_back(result.peakRssMiB);
            bytes.push_back(vpe::benchmarks::bytesOnDisk(model));
            std::printf("run %d: %.2f s end to end;", run + 1, result.seconds);
            for (int p = 0; p < 4; ++p) {
                phaseSeconds[p].push_back(result.report["seconds"][phases[p]].get<double>());
                std::printf(" %s %.2f s", phases[p], phaseSeconds[p].back());
            }
            std::printf("; peak RSS %.0f MiB; model %.1f MB\n", rss.back(), bytes.back() / 1e6);
            std::fflush(stdout);
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 1;
    }
    std::filesystem::remove(model);
    using vpe::benchmarks::median;
    const double pixels = static_cast<double>(size) * size;
    std::printf(
        "330 x %dx%d capture, median of %d: vpe fit %.2f s end to end (%.0f pixels/s; goal at "
        "2048²: <= 15 s);",
        size, size, runs, median(totals), pixels / median(totals));
    for (int p = 0; p < 4; ++p) {
        std::printf(" %s %.2f s", phases[p], median(phaseSeconds[p]));
    }
    std::printf("; fit alone %.2f M pixels/s; peak RSS %.0f MiB (goal <= 1024); model %.1f MB\n",
                pixels / median(phaseSeconds[2]) / 1e6, median(rss), median(bytes) / 1e6);
    return 0;
}
