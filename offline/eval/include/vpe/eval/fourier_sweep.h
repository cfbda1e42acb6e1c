// SPDX-License-Identifier: MIT
// runSweep: the paper's Fig. 6. Fits TRAIN for every M in 1..maxHarmonics and every λ, and
// scores each fit on TEST (same metric as vpe eval). The normal equations of all M come
// from one accumulation at the largest M (the interleaved layout makes smaller models
// prefixes), so the sweep costs little more than a single fit plus the solves.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::eval {

struct SweepOptions {
    int maxHarmonics = 15;
    std::vector<double> lambdas{0.0, 0.5, 3.14, 10.0, 50.0};
    unsigned threads = 1;
    std::optional<std::filesystem::path> normals;  // for TRAIN; else its own or estimated
};

struct SweepResult {
    std::vector<int> harmonics;  // 1..maxHarmonics
    std::vector<double> lambdas;
    std::vector<std::vector<double>> rms;   // [λ][M index], 8-bit levels, pooled over TEST
    std::vector<std::vector<double>> psnr;  // [λ][M index], mean of per-image PSNR
    std::vector<std::vector<double>> validFraction;  // [λ][M index]
    int trainImages = 0;
    int testImages = 0;
    std::size_t pixels = 0;
    std::string normalsSource;
    double seconds = 0;
};

SweepResult runSweep(const capture::Capture& train, const capture::Capture& test,
                     const SweepOptions& options);

void writeSweepCsv(const std::filesystem::path& path, const SweepResult& result);
void writeSweepPlot(const std::filesystem::path& path, const SweepResult& result);

}  // namespace vpe::eval
