// SPDX-License-Identifier: MIT
// Blends region maps band by band: K readers and one writer, never a whole map in memory.
#include "vpe/texture/region_compose.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::texture {

namespace {

constexpr int kBandRows = 32;

}  // namespace

model::ModelInfo checkRegionMaps(const std::vector<std::filesystem::path>& regionMaps) {
    if (regionMaps.empty()) {
        throw common::InputError("no region maps to compose");
    }
    model::ModelInfo first;
    for (std::size_t k = 0; k < regionMaps.size(); ++k) {
        const model::ModelReader reader(regionMaps[k]);
        const model::ModelInfo& info = reader.info();
        if (k == 0) {
            first = info;
            continue;
        }
        if (info.width != first.width || info.height != first.height) {
            throw common::InputError(
                regionMaps[k],
                "size " + std::to_string(info.width) + " × " + std::to_string(info.height) +
                    " differs from " + regionMaps[0].filename().string() + "'s " +
                    std::to_string(first.width) + " × " + std::to_string(first.height));
        }
        if (info.harmonics != first.harmonics) {
            throw common::InputError(regionMaps[k], std::to_string(info.harmonics) +
                                                        " harmonics, but " +
                                                        regionMaps[0].filename().string() +
                                                        " has " + std::to_string(first.harmonics));
        }
    }
    return first;
}

ComposeReport composeRegionMaps(const std::vector<std::filesystem::path>& regionMaps,
                                const WeightMaps& weights, const std::filesystem::path& out,
                                std::optional<model::ModelStorage> storage) {
    const model::ModelInfo first = checkRegionMaps(regionMaps);
    const int regions = static_cast<int>(regionMaps.size());
    if (weights.regions() != regions || weights.width != first.width ||
        weights.height != first.height) {
        throw common::InputError(
            out, "weight maps (" + std::to_string(weights.regions()) + " of " +
                     std::to_string(weights.width) + " × " + std::to_string(weights.height) +
                     ") do not match the " + std::to_string(regions) + " region maps of " +
                     std::to_string(first.width) + " × " + std::to_string(first.height));
    }
    ComposeReport report;
    report.width = first.width;
    report.height = first.height;
    report.harmonics = first.harmonics;
    report.regions = regions;
    report.meanWeight.assign(static_cast<std::size_t>(regions), 0.0);

    model::ModelInfo info = model::fourierModelInfo(first.width, first.height, first.harmonics,
                                                    first.lambda, first.samples);
    // A synthesized texture is material only: the extended model's light transport and
    // capture geometry belong to the captured object, so the composite is the paper variant.
    info.variant = "paper";
    info.storage = storage.value_or(first.storage);
    info.capture = "composed from " + std::to_string(regions) + " region maps in " +
                   regionMaps[0].parent_path().string();
    // The relief is blended as the coefficients are (a region without one is flat there).
    for (const auto& path : regionMaps) {
        info.detailNormals = info.detailNormals || model::ModelReader(path).info().detailNormals;
    }

    std::vector<std::unique_ptr<model::ModelReader>> readers;
    for (const auto& path : regionMaps) {
        readers.push_back(std::make_unique<model::ModelReader>(path));
    }
    model::ModelWriter writer(out, info);
    const int k = proto::coefficientCount(first.harmonics);
    const auto perPixel = static_cast<std::size_t>(3 * k);
    std::vector<model::ModelRows> inputs(static_cast<std::size_t>(regions));
    model::ModelRows rows;
    std::vector<double> coefficient(perPixel);
    for (int rowBegin = 0; rowBegin < first.height; rowBegin += kBandRows) {
        const int bandRows = std::min(kBandRows, first.height - rowBegin);
        for (int r = 0; r < regions; ++r) {
            readers[static_cast<std::size_t>(r)]->readRows(rowBegin, bandRows,
                                                           inputs[static_cast<std::size_t>(r)]);
        }
        rows.resize(first.width, bandRows, k, false, info.detailNormals);
        for (int y = 0; y < bandRows; ++y) {
            for (int x = 0; x < first.width; ++x) {
                const std::size_t p = rows.pixel(y, x);
                std::fill(coefficient.begin(), coefficient.end(), 0.0);
                double rms[3] = {0, 0, 0};
                double detail[3] = {0, 0, 0};
                bool valid = true;
                for (int r = 0; r < regions; ++r) {
                    const model::ModelRows& in = inputs[static_cast<std::size_t>(r)];
                    const double alpha = static_cast<double>(weights.at(r, x, rowBegin + y));
                    report.meanWeight[static_cast<std::size_t>(r)] += alpha;
                    if (alpha == 0) {
                        continue;  // an invalid pixel of an unused region does not matter
                    }
                    if (!in.valid[p]) {
                        valid = false;
                        continue;
                    }
                    // Accumulated in double and rounded once: the composite is the exact
                    // blend to float precision.
                    const float* c = in.coefficient.data() + p * perPixel;
                    for (std::size_t i = 0; i < perPixel; ++i) {
                        coefficient[i] += alpha * static_cast<double>(c[i]);
                    }
                    for (int ch = 0; ch < 3; ++ch) {
                        rms[ch] += alpha * static_cast<double>(in.rms[p * 3 + ch]);
                        detail[ch] += alpha * (in.detail.empty()
                                                   ? (ch == 2 ? 1.0 : 0.0)
                                                   : static_cast<double>(in.detail[p * 3 + ch]));
                    }
                }
                // Texture maps carry no geometry: the bake supplies the object's normals.
                rows.normal[p * 3 + 2] = 1.0f;
                if (!valid) {
                    ++report.invalidPixels;
                    continue;  // invalid pixels hold zeros
                }
                rows.valid[p] = 1;
                for (std::size_t i = 0; i < perPixel; ++i) {
                    rows.coefficient[p * perPixel + i] = static_cast<float>(coefficient[i]);
                }
                for (int ch = 0; ch < 3; ++ch) {
                    rows.rms[p * 3 + ch] = static_cast<float>(rms[ch]);
                }
                if (info.detailNormals) {
                    const double length = std::sqrt(detail[0] * detail[0] + detail[1] * detail[1] +
                                                    detail[2] * detail[2]);
                    for (int ch = 0; ch < 3; ++ch) {
                        rows.detail[p * 3 + ch] =
                            length > 0 ? static_cast<float>(detail[ch] / length) : (ch == 2);
                    }
                }
            }
        }
        writer.writeRows(rowBegin, rows);
    }
    writer.finish();
    const double pixels = static_cast<double>(first.width) * first.height;
    for (double& mean : report.meanWeight) {
        mean /= pixels;
    }
    return report;
}

}  // namespace vpe::texture
