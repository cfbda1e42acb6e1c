// SPDX-License-Identifier: MIT
// Bundle load time on the device's path: a 2048² two-region bundle (low-rank, rank 12, M = 10,
// plus one 8-bit weight preset) is written to a temporary folder, then opened — mapped,
// validated and ready to upload — repeatedly: median of the runs with the CRC-32 pass, and
// without it (a device that verified the bundle once after installing it). The file is in the
// page cache, so this is the cost of checking, not of reading the storage.
//   vpe_bundle_load_benchmark [--size 2048] [--rank 12] [--repeat 5]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "vpe/bake/bundle_writer.h"

#include "benchmark_bundle.h"

namespace {

using vpe::bake::BundleContents;

BundleContents benchmarkContents(int size, int rank) {
    BundleContents c;
    c.mesh = vpe::benchmarks::planeMesh(64, 0.2f, -0.2f, 1.0f);
    c.projector = vpe::benchmarks::benchmarkProjector();
    c.settings.viewerPosition = {0.0f, 0.2f, 1.5f};
    vpe::benchmarks::usePaperModel(c, size);
    const auto values = static_cast<std::size_t>(c.model.coefficientsPerTexel());
    const auto r = static_cast<std::size_t>(rank);
    const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
    for (int region = 0; region < 2; ++region) {
        vpe::bake::BundleRegion entry = vpe::benchmarks::lowRankRegion(region, rank);
        vpe::bake::CoefficientMapData& map = entry.coefficients;
        map.mean.assign(values, 0.1f);
        map.basis.resize(r * values);
        for (std::size_t i = 0; i < map.basis.size(); ++i) {
            map.basis[i] = std::sin(0.1f * static_cast<float>(i + 7 * region));
        }
        map.weights.resize(texels * r);
        for (std::size_t i = 0; i < map.weights.size(); ++i) {
            map.weights[i] = static_cast<float>((i * 2654435761u + region) % 1000) / 500.0f - 1.0f;
        }
        c.regions.push_back(std::move(entry));
    }
    c.presets.push_back(vpe::benchmarks::stripesPreset(size));
    return c;
}

double seconds(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Opens the bundle `repeat` times; returns the median in seconds.
double openMedian(const std::filesystem::path& path, int repeat, bool checksum) {
    std::vector<double> times;
    for (int i = 0; i < repeat; ++i) {
        const auto start = std::chrono::steady_clock::now();
        const vpe::proto::BundleFile file =
            vpe::proto::BundleFile::open(path, {.verifyChecksum = checksum});
        times.push_back(seconds(start));
        if (file->regions().size() != 2) {
            std::abort();
        }
    }
    return median(times);
}

}  // namespace

int main(int argc, char** argv) {
    int size = 2048;
    int rank = 12;
    int repeat = 5;
    for (int i = 1; i + 1 < argc; i += 2) {
        const int value = std::atoi(argv[i + 1]);
        if (std::strcmp(argv[i], "--size") == 0) {
            size = value;
        } else if (std::strcmp(argv[i], "--rank") == 0) {
            rank = value;
        } else if (std::strcmp(argv[i], "--repeat") == 0) {
            repeat = value;
        }
    }
    const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                         ("vpe-bundle-benchmark-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    const std::filesystem::path path = folder / "scene.vpeb";
    int status = 0;
    try {
        const BundleContents contents = benchmarkContents(size, rank);
        const auto start = std::chrono::steady_clock::now();
        const vpe::bake::BundleWriteResult written = vpe::bake::writeBundle(path, contents);
        std::printf(
            "wrote %d² x 2 regions, low-rank rank %d (M = %d), 1 preset: %.1f MiB in %.2f s\n",
            size, rank, contents.model.harmonics,
            static_cast<double>(written.bytes) / (1024.0 * 1024.0), seconds(start));
        openMedian(path, 1, true);  // warm the page cache
        const double withChecksum = openMedian(path, repeat, true);
        const double withoutChecksum = openMedian(path, repeat, false);
        std::printf("open, verified with checksum:  median %.2f ms of %d (%.2f GB/s)\n",
                    1e3 * withChecksum, repeat,
                    static_cast<double>(written.bytes) / withChecksum / 1e9);
        std::printf("open, structure only:          median %.3f ms of %d\n", 1e3 * withoutChecksum,
                    repeat);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_bundle_load_benchmark: %s\n", error.what());
        status = 1;
    }
    std::error_code ignored;
    std::filesystem::remove_all(folder, ignored);
    return status;
}
