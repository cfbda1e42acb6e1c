// SPDX-License-Identifier: MIT
// The texture commands as users run them, on one recipe: the synthetic pot at 512²
// (`vpe synth --size 512 --seed 2`, 330 training images), fitted and split into two regions
// once into a cache folder; then, `--runs` times each (default 3), as child processes:
//   fit    `vpe fit S/train`: the command's phases and its fitting rate (seconds.fit; goal
//          ≥ 1 M pixels/s, the kernel benchmark's rate);
//   quilt  `vpe quilt M.exr --size 2048x2048 --seed 3`: wall time (goal ≤ 10 s) with the
//          command's load, quilt and write phases, and the size of what it writes.
// Medians at the end. The kernels alone: vpe_fit_benchmark, vpe_quilt_benchmark. `--vpe PATH`
// times another build of vpe (a before/after comparison); the cache is made by the one timed.
// `--simd AVX3,AVX2` runs the fit on each SIMD target named (VPE_SIMD), in turn within each run,
// and gives each one's medians and their ratios to the first's.
//   vpe_command_benchmark [fit|quilt|all] [--dir DIR] [--runs 3] [--vpe PATH] [--simd LIST]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runs.h"
#include "test_paths.h"

namespace {

using vpe::benchmarks::CommandRun;
using vpe::benchmarks::median;
using vpe::benchmarks::runCommand;

std::string kVpe = vpe::test_paths::vpeExecutablePath();

// The recipe's inputs, made once by the vpe under test.
void prepare(const std::filesystem::path& dir) {
    if (std::filesystem::exists(dir / "L.png")) {
        return;
    }
    std::fprintf(stderr, "preparing the synthetic pot (512², seed 2) in %s ...\n", dir.c_str());
    std::filesystem::create_directories(dir);
    const std::string s = (dir / "S").string(), m = (dir / "M.exr").string();
    runCommand({kVpe, "synth", "--size", "512", "--seed", "2", "--out", s, "--json"});
    runCommand({kVpe, "fit", s + "/train", "--out", m, "--json"});
    runCommand({kVpe, "segment", m, "--auto", "2", "--out", (dir / "L.png").string(), "--json"});
}

// `targets`: the SIMD targets to run the fit on (VPE_SIMD), taken in turn within each run so
// that every target sees the same moments of a busy machine; empty, the best the CPU has.
void benchmarkFit(const std::filesystem::path& dir, int runs,
                  const std::vector<std::string>& targets) {
    const std::string model = (dir / "fit-run.exr").string();
    const char* const phases[] = {"decode", "normals", "fit", "write"};
    const std::vector<std::string> each = targets.empty() ? std::vector<std::string>{""} : targets;
    struct Figures {
        std::vector<double> totals, rates, phaseSeconds[4];
    };
    std::vector<Figures> figures(each.size());
    double pixels = 0;
    for (int run = 0; run < runs; ++run) {
        for (std::size_t t = 0; t < each.size(); ++t) {
            if (each[t].empty()) {
                unsetenv("VPE_SIMD");
            } else {
                setenv("VPE_SIMD", each[t].c_str(), 1);
            }
            const CommandRun result =
                runCommand({kVpe, "fit", (dir / "S" / "train").string(), "--out", model, "--json"});
            Figures& f = figures[t];
            pixels = result.report["pixels"].get<double>();
            f.totals.push_back(result.seconds);
            std::printf("fit run %d (%s): %.2f s end to end;", run + 1,
                        result.report.value("simd", std::string("?")).c_str(), result.seconds);
            for (int p = 0; p < 4; ++p) {
                f.phaseSeconds[p].push_back(result.report["seconds"][phases[p]].get<double>());
                std::printf(" %s %.3f s", phases[p], f.phaseSeconds[p].back());
            }
            f.rates.push_back(pixels / f.phaseSeconds[2].back() / 1e6);
            std::printf("; fit %.2f M pixels/s\n", f.rates.back());
            std::fflush(stdout);
        }
    }
    unsetenv("VPE_SIMD");
    std::filesystem::remove(model);
    std::filesystem::remove(dir / "fit-run.preview.png");
    for (std::size_t t = 0; t < each.size(); ++t) {
        const Figures& f = figures[t];
        std::printf("vpe fit%s%s, 330 × 512² synthetic pot, median of %d: %.2f s end to end;",
                    each[t].empty() ? "" : " on ", each[t].c_str(), runs, median(f.totals));
        for (int p = 0; p < 4; ++p) {
            std::printf(" %s %.3f s", phases[p], median(f.phaseSeconds[p]));
        }
        std::printf("; seconds.fit at %.2f M pixels/s (goal >= 1)", median(f.rates));
        if (t > 0) {
            std::printf("; against %s: seconds.fit %.2fx, end to end %.2fx", each[0].c_str(),
                        median(f.phaseSeconds[2]) / median(figures[0].phaseSeconds[2]),
                        median(f.totals) / median(figures[0].totals));
        }
        std::printf("\n");
    }
}

void benchmarkQuilt(const std::filesystem::path& dir, int runs) {
    const std::string out = (dir / "Q").string();
    const char* const phases[] = {"load_seconds", "quilt_seconds", "write_seconds"};
    std::vector<double> totals, own, bytes, phaseSeconds[3];
    for (int run = 0; run < runs; ++run) {
        std::filesystem::remove_all(out);
        const CommandRun result = runCommand({kVpe, "quilt", (dir / "M.exr").string(), "--labels",
                                              (dir / "L.png").string(), "--size", "2048x2048",
                                              "--seed", "3", "--out", out, "--json"});
        totals.push_back(result.seconds);
        own.push_back(result.report["seconds"].get<double>());
        bytes.push_back(vpe::benchmarks::bytesOnDisk(out));
        std::printf("quilt run %d: %.2f s end to end (its own seconds %.2f);", run + 1,
                    result.seconds, own.back());
        for (int p = 0; p < 3; ++p) {
            // NaN from a vpe that does not report the phase (older builds).
            phaseSeconds[p].push_back(result.report.value(phases[p], std::nan("")));
            std::printf(" %s %.2f", phases[p], phaseSeconds[p].back());
        }
        std::printf("; peak RSS %.0f MiB; wrote %.1f MB\n", result.peakRssMiB, bytes.back() / 1e6);
        std::fflush(stdout);
    }
    std::filesystem::remove_all(out);
    std::printf(
        "vpe quilt 512² → 2048², synthetic pot, median of %d: %.2f s end to end (goal "
        "<= 10 s; its own seconds %.2f);",
        runs, median(totals), median(own));
    for (int p = 0; p < 3; ++p) {
        std::printf(" %s %.2f", phases[p], median(phaseSeconds[p]));
    }
    std::printf("; wrote %.1f MB\n", median(bytes) / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
    std::string mode = "all";
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "vpe-command-benchmark";
    int runs = 3;
    std::vector<std::string> targets;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--dir") == 0 && i + 1 < argc) {
            dir = argv[++i];
        } else if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
            runs = std::max(1, std::atoi(argv[++i]));
        } else if (std::strcmp(argv[i], "--vpe") == 0 && i + 1 < argc) {
            kVpe = argv[++i];
        } else if (std::strcmp(argv[i], "--simd") == 0 && i + 1 < argc) {
            std::string list = argv[++i];
            for (std::size_t at = 0; at <= list.size();) {
                const std::size_t comma = std::min(list.find(',', at), list.size());
                targets.push_back(list.substr(at, comma - at));
                at = comma + 1;
            }
        } else {
            mode = argv[i];
        }
    }
    if (mode != "fit" && mode != "quilt" && mode != "all") {
        std::fprintf(stderr,
                     "usage: vpe_command_benchmark [fit|quilt|all] [--dir DIR] [--runs N] "
                     "[--vpe PATH] [--simd AVX3,AVX2,...]\n");
        return 2;
    }
    try {
        prepare(dir);
        if (mode != "quilt") {
            benchmarkFit(dir, runs, targets);
        }
        if (mode != "fit") {
            benchmarkQuilt(dir, runs);
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "%s\n", error.what());
        return 1;
    }
    return 0;
}
