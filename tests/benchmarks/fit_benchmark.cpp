// SPDX-License-Identifier: MIT
// Fitting speed: N = 330 lights (the paper's rig), M = 10, RGB, a normal per pixel, on all
// cores. BM_FitBand runs `vpe fit`'s own band stage (BandFitter); BM_NaivePerPixel is the
// textbook per-pixel fit (build A, AᵀA + λR, LDLT) on the same threads. The run ends with
// the ratio of the two. BM_FitBandOnTarget/<target> runs the band stage on each SIMD target the
// kernels are compiled for and this CPU runs (AVX3 = AVX-512, AVX2, SSE4, NEON, ...), each
// against the same naive rate; BM_FitBandExtendedOnTarget/<target> the extended fit with the
// normal search. Decoding is not included: see vpe_fit_memory_benchmark for the
// end-to-end figure.
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include <benchmark/benchmark.h>
#include <hwy/targets.h>

#include "vpe/capture/surface_geometry.h"
#include "vpe/common/parallel_for.h"
#include "vpe/fit/band_fitter.h"
#include "vpe/fit/naive_fourier_fit.h"
#include "vpe/fit/normal_equations.h"

#include "paper_rig.h"

namespace vpe {
namespace {

constexpr int kHarmonics = 10;
constexpr double kLambda = 3.14;

// A band of a capture rendered from per-pixel Fourier coefficients under the paper's rig.
struct BenchmarkBand {
    capture::Capture capture;
    normals::NormalMap normals;
    capture::SampleBand band;

    BenchmarkBand(int width, int rows) {
        for (const proto::Vec3d& light : benchmarks::paperRigLights()) {
            capture.images.push_back({"", light, 1.0, 0});
        }
        std::mt19937 random(1);
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        normals.resize(width, rows);
        for (int i = 0; i < width * rows; ++i) {
            const proto::Vec3d n =
                proto::normalized(proto::Vec3d{0.4 * uniform(random), 0.4 * uniform(random), 1.0});
            normals.xyz[static_cast<std::size_t>(i) * 3] = static_cast<float>(n.x);
            normals.xyz[static_cast<std::size_t>(i) * 3 + 1] = static_cast<float>(n.y);
            normals.xyz[static_cast<std::size_t>(i) * 3 + 2] = static_cast<float>(n.z);
            normals.valid[static_cast<std::size_t>(i)] = 1;
        }
        band.resize(static_cast<int>(capture.images.size()), width, rows);
        const int k = proto::coefficientCount(kHarmonics);
        std::vector<double> coefficients(static_cast<std::size_t>(k));
        for (int r = 0; r < rows; ++r) {
            for (int x = 0; x < width; ++x) {
                for (int c = 0; c < 3; ++c) {
                    for (int j = 0; j < k; ++j) {
                        coefficients[static_cast<std::size_t>(j)] =
                            j == 0 ? 0.5 : 0.1 * uniform(random) / (1 + j / 2);
                    }
                    for (int s = 0; s < band.images; ++s) {
                        const auto angles = proto::reflectionAngles(
                            normals.at(x, r), capture.images[static_cast<std::size_t>(s)].light,
                            proto::Vec3d{0, 0, 1});
                        band.values[band.valueIndex(s, c, r, x)] = static_cast<float>(
                            proto::evaluateFourierBrdf(coefficients.data(), kHarmonics,
                                                       angles.cosThetaD, angles.cosThetaS));
                    }
                }
                for (int s = 0; s < band.images; ++s) {
                    band.weights[band.sampleIndex(s, r, x)] = 1.0f;
                }
            }
        }
        band.markFullyUsableChunks();
    }
};

const BenchmarkBand& sharedBand() {
    // The band `vpe fit` processes for a 330-image 2048-wide capture (192 MiB budget).
    static const BenchmarkBand band(2048, 16);
    return band;
}

// BandFitter over `data` with M = 10, λ = 3.14 on all cores; reports its pixel rate.
void measureBandFit(benchmark::State& state, const BenchmarkBand& data,
                    fit::BandFitSettings settings) {
    const capture::SurfaceGeometry geometry(data.capture, data.band.width, data.band.rows);
    settings.fit.harmonics = kHarmonics;
    settings.fit.lambda = kLambda;
    settings.threads = common::resolveThreadCount(0);
    const fit::BandFitter fitter(data.capture, geometry, data.normals, settings);
    model::ModelRows rows;
    for (auto _ : state) {
        fitter.fit(data.band, rows);
        benchmark::DoNotOptimize(rows.coefficient.data());
    }
    const double pixels = static_cast<double>(data.band.width) * data.band.rows;
    state.counters["pixels_per_second"] = benchmark::Counter(
        pixels * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["threads"] = settings.threads;
}

void BM_FitBand(benchmark::State& state) {
    measureBandFit(state, sharedBand(), fit::BandFitSettings{});
}

// The band stage with the kernels restricted to one SIMD target.
void fitBandOnTarget(benchmark::State& state, std::int64_t target) {
    hwy::SetSupportedTargetsForTest(target);
    if (fit::activeKernelTarget() == target) {
        measureBandFit(state, sharedBand(), fit::BandFitSettings{});
    } else {
        state.SkipWithError("the kernels did not switch to this target");
    }
    hwy::SetSupportedTargetsForTest(0);
}

// The extended fit on a narrower band of the same kind: with the normal search it runs 13
// alternating fits per texel.
void fitBandExtended(benchmark::State& state, double normalSearchDegrees) {
    static const BenchmarkBand data(256, 16);
    fit::BandFitSettings settings;
    settings.extended = true;
    settings.fit.normalSearchDegrees = normalSearchDegrees;
    measureBandFit(state, data, settings);
}

void BM_FitBandExtended(benchmark::State& state) {
    fitBandExtended(state, static_cast<double>(state.range(0)));
}

// The extended fit with the normal search, its kernels restricted to one SIMD target.
void fitBandExtendedOnTarget(benchmark::State& state, std::int64_t target) {
    hwy::SetSupportedTargetsForTest(target);
    if (fit::activeKernelTarget() == target) {
        fitBandExtended(state, 4);
    } else {
        state.SkipWithError("the kernels did not switch to this target");
    }
    hwy::SetSupportedTargetsForTest(0);
}

void registerTargetBenchmarks() {
    for (const std::int64_t target : fit::kernelTargets()) {
        const std::string name = std::string("BM_FitBandOnTarget/") + hwy::TargetName(target);
        benchmark::RegisterBenchmark(name.c_str(), fitBandOnTarget, target)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(2.0);
    }
    for (const std::int64_t target : fit::kernelTargets()) {
        const std::string name =
            std::string("BM_FitBandExtendedOnTarget/") + hwy::TargetName(target);
        benchmark::RegisterBenchmark(name.c_str(), fitBandExtendedOnTarget, target)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond)
            ->MinTime(2.0);
    }
}

void BM_NaivePerPixel(benchmark::State& state) {
    const BenchmarkBand& data = sharedBand();
    const int pixels = 512;  // the baseline is slow; one row of the same band
    const unsigned threads = common::resolveThreadCount(0);
    const int samples = data.band.images;
    for (auto _ : state) {
        common::parallelFor(
            static_cast<std::size_t>(pixels), 16, threads, [&](std::size_t begin, std::size_t end) {
                std::vector<proto::ReflectionAngles<double>> angles(
                    static_cast<std::size_t>(samples));
                Eigen::MatrixX3d y(samples, 3);
                const Eigen::VectorXd w = Eigen::VectorXd::Ones(samples);
                for (std::size_t x = begin; x < end; ++x) {
                    const int xi = static_cast<int>(x);
                    for (int s = 0; s < samples; ++s) {
                        angles[static_cast<std::size_t>(s)] = proto::reflectionAngles(
                            data.normals.at(xi, 0),
                            data.capture.images[static_cast<std::size_t>(s)].light,
                            proto::Vec3d{0, 0, 1});
                        for (int c = 0; c < 3; ++c) {
                            y(s, c) = data.band.value(s, c, 0, xi);
                        }
                    }
                    benchmark::DoNotOptimize(fit::fitPixelNaive(angles, y, w, kHarmonics, kLambda));
                }
            });
    }
    state.counters["pixels_per_second"] =
        benchmark::Counter(static_cast<double>(pixels) * static_cast<double>(state.iterations()),
                           benchmark::Counter::kIsRate);
    state.counters["threads"] = threads;
}

BENCHMARK(BM_FitBand)->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FitBandExtended)
    ->Arg(0)
    ->Arg(4)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
BENCHMARK(BM_NaivePerPixel)->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

// Prints the ratio of the two benchmarks' pixel rates after the usual table.
class RatioReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            const auto it = run.counters.find("pixels_per_second");
            if (it != run.counters.end() && run.run_type == Run::RT_Iteration) {
                rates_[run.benchmark_name()] = it->second.value;
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }
    void Finalize() override {
        ConsoleReporter::Finalize();
        double fast = 0, naive = 0, extended = 0, refining = 0;
        std::map<std::string, double> onTarget, extendedOnTarget;  // by target name
        const auto byTarget = [](const std::string& name, const std::string& prefix,
                                 std::map<std::string, double>& rates, double rate) {
            if (name.rfind(prefix, 0) != 0) {
                return false;
            }
            const std::size_t end = name.find('/', prefix.size());
            rates[name.substr(prefix.size(), end - prefix.size())] = rate;
            return true;
        };
        for (const auto& [name, rate] : rates_) {
            if (byTarget(name, "BM_FitBandOnTarget/", onTarget, rate) ||
                byTarget(name, "BM_FitBandExtendedOnTarget/", extendedOnTarget, rate)) {
                continue;
            }
            if (name.rfind("BM_FitBand/", 0) == 0) {
                fast = rate;
            } else if (name.rfind("BM_NaivePerPixel", 0) == 0) {
                naive = rate;
            } else if (name.rfind("BM_FitBandExtended/0/", 0) == 0) {
                extended = rate;
            } else if (name.rfind("BM_FitBandExtended/4/", 0) == 0) {
                refining = rate;
            }
        }
        if (fast > 0 && naive > 0) {
            std::printf(
                "\nfit: %.0f pixels/s; naive per-pixel baseline: %.0f pixels/s; ratio %.1fx\n",
                fast, naive, fast / naive);
        }
        for (const auto& [target, rate] : onTarget) {
            if (naive > 0) {
                std::printf("fit on %s: %.0f pixels/s; ratio %.1fx to the naive fit\n",
                            target.c_str(), rate, rate / naive);
            }
        }
        if (extended > 0 && refining > 0) {
            std::printf(
                "extended fit: %.0f pixels/s; with the normal search: %.0f pixels/s "
                "(%.1fx the time)\n",
                extended, refining, extended / refining);
        }
        for (const auto& [target, rate] : extendedOnTarget) {
            std::printf("extended fit with the normal search on %s: %.0f pixels/s\n",
                        target.c_str(), rate);
        }
    }

private:
    std::map<std::string, double> rates_;
};

}  // namespace
}  // namespace vpe

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    vpe::registerTargetBenchmarks();
    vpe::RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    return 0;
}
