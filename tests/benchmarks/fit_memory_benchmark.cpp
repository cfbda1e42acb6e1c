// SPDX-License-Identifier: MIT
// Memory and end-to-end speed of `vpe fit` on the paper's capture size: 330 images of
// 2048 × 2048 (8-bit sRGB JPEG, a normal map beside them). The capture is rendered once into
// a cache folder; `vpe fit` then runs as a child process and its peak RSS comes from wait4.
//   vpe_fit_memory_benchmark [--size N] [--dir DIR]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include "vpe/proto/srgb.h"

#include "common/parallel_for.h"
#include "paper_rig.h"

extern char** environ;

namespace vpe {
namespace {

// A glazed, rippled surface: normals from a height field, albedo streaks, a specular lobe.
Vec3d surfaceNormal(int x, int y, int size) {
    const double u = 12.0 * M_PI * x / size, v = 9.0 * M_PI * y / size;
    const double dx = 0.25 * std::cos(u) * std::cos(0.5 * v);
    const double dy = -0.125 * std::sin(u) * std::sin(0.5 * v) + 0.15 * std::cos(v);
    return proto::normalized(Vec3d{-dx, -dy, 1.0});
}

void writeCapture(const std::filesystem::path& dir, int size) {
    std::filesystem::create_directories(dir);
    const std::vector<Vec3d> lights = benchmarks::paperRigLights();
    std::vector<float> normals(static_cast<std::size_t>(size) * size * 3);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const Vec3d n = surfaceNormal(x, y, size);
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
    parallelFor(lights.size(), 1, resolveThreadCount(0), [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint8_t> pixels(static_cast<std::size_t>(size) * size * 3);
        for (std::size_t i = begin; i < end; ++i) {
            const Vec3d l = lights[i];
            for (int y = 0; y < size; ++y) {
                for (int x = 0; x < size; ++x) {
                    const Vec3d n = surfaceNormal(x, y, size);
                    const double nl = std::max(0.0, proto::dot(n, l));
                    const Vec3d h = proto::normalized(Vec3d{l.x, l.y, l.z + 1.0});
                    const double specular = 0.4 * std::pow(std::max(0.0, proto::dot(n, h)), 40.0);
                    const double streak = 0.5 + 0.5 * std::sin(0.01 * (x + 2 * y));
                    const double albedo[3] = {0.35 + 0.3 * streak, 0.25 + 0.1 * streak, 0.2};
                    for (int c = 0; c < 3; ++c) {
                        const double linear = std::min(1.0, albedo[c] * nl + specular * nl + 0.01);
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
    std::filesystem::path dir;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::strcmp(argv[i], "--size") == 0) {
            size = std::atoi(argv[i + 1]);
        } else if (std::strcmp(argv[i], "--dir") == 0) {
            dir = argv[i + 1];
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
    std::vector<std::string> arguments{
        VPE_EXECUTABLE_PATH, "fit", dir.string(), "--out", model, "--json"};
    std::vector<char*> argvChild;
    for (std::string& a : arguments) {
        argvChild.push_back(a.data());
    }
    argvChild.push_back(nullptr);
    const auto start = Clock::now();
    pid_t pid = 0;
    if (posix_spawn(&pid, argvChild[0], nullptr, nullptr, argvChild.data(), environ) != 0) {
        std::fprintf(stderr, "cannot start %s\n", argvChild[0]);
        return 1;
    }
    int status = 0;
    rusage usage{};
    wait4(pid, &status, 0, &usage);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "vpe fit failed\n");
        return 1;
    }
    const double pixels = static_cast<double>(size) * size;
    std::printf(
        "330 x %dx%d capture: vpe fit took %.1f s (%.0f pixels/s end to end, decode included); "
        "peak RSS %.0f MiB\n",
        size, size, seconds, pixels / seconds, static_cast<double>(usage.ru_maxrss) / 1024.0);
    std::filesystem::remove(model);
    return 0;
}
