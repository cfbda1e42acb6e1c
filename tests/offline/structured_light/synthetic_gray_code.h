// SPDX-License-Identifier: MIT
// A Gray-code capture drawn without the simulator, for the decoder's and the importer's tests: a
// flat target filling the camera's view, camera pixel (u, v) seeing projector point
// (offset + u·scale, offset + v·scale); each image the black level plus the albedo times the
// pattern's level averaged over the pixel's footprint, plus Gaussian noise, in 8 bits. Written
// as a vpe scan folder (PGM) or as procam-calibration lays out its captures (PNG), and such a
// capture (a real one too) rewritten in the other formats its cameras may write.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "vpe/image/image_file.h"
#include "vpe/proto/pnm_image.h"
#include "vpe/proto/scan_manifest.h"
#include "vpe/proto/structured_light.h"

namespace vpe::testing {

struct SyntheticGrayCode {
    proto::StructuredLightParameters patterns{64, 48, 32, 0};
    int cameraWidth = 160, cameraHeight = 120;
    double scale = 0.37, offset = 0.3;  // projector pixels per camera pixel; the first's place
    double footprint = 0;               // projector pixels a camera pixel averages (0: a point)
    double black = 0.05, albedo = 0.6, noise = 0.004;
    unsigned seed = 1;

    double projectorX(int u) const { return offset + u * scale; }
    double projectorY(int v) const { return offset + v * scale; }
};

// The pattern as the camera records it, 8-bit, rows from the top.
inline std::vector<std::uint8_t> photographPattern(const SyntheticGrayCode& capture,
                                                   const proto::PatternSpec& pattern,
                                                   std::mt19937& random) {
    const proto::StructuredLightSequence sequence(capture.patterns);
    std::normal_distribution<double> noise(0.0, capture.noise);
    constexpr int kSamples = 16;
    // The level a point at projector coordinate c sees: column (row) c covers [c − ½, c + ½).
    const auto levelAt = [&](double x, double y) {
        const int column =
            std::clamp(static_cast<int>(std::floor(x + 0.5)), 0, capture.patterns.width - 1);
        const int row =
            std::clamp(static_cast<int>(std::floor(y + 0.5)), 0, capture.patterns.height - 1);
        return sequence.level(pattern, column, row);
    };
    std::vector<std::uint8_t> image(static_cast<std::size_t>(capture.cameraWidth) *
                                    capture.cameraHeight);
    for (int v = 0; v < capture.cameraHeight; ++v) {
        for (int u = 0; u < capture.cameraWidth; ++u) {
            const double x = capture.projectorX(u), y = capture.projectorY(v);
            double level = 0;
            if (capture.footprint == 0) {
                level = levelAt(x, y);
            } else {
                // Every pattern varies along one axis: average along both, sample by sample.
                for (int s = 0; s < kSamples; ++s) {
                    const double along = capture.footprint * ((s + 0.5) / kSamples - 0.5);
                    level += levelAt(x + along, y + along) / kSamples;
                }
            }
            const double value = capture.black + capture.albedo * level + noise(random);
            image[static_cast<std::size_t>(v) * capture.cameraWidth + u] =
                static_cast<std::uint8_t>(std::lround(255 * std::clamp(value, 0.0, 1.0)));
        }
    }
    return image;
}

// The tool's order: the Gray pairs (columns, then rows, each bit then its inverse), then white
// and black when shown.
inline std::vector<proto::PatternSpec> toolOrder(const proto::StructuredLightParameters& patterns) {
    const proto::StructuredLightSequence sequence(patterns);
    std::vector<proto::PatternSpec> order;
    for (const proto::PatternSpec& pattern : sequence.patterns()) {
        if (pattern.kind == proto::PatternKind::kGray) {
            order.push_back(pattern);
        }
    }
    if (patterns.flatFields) {
        order.push_back({proto::PatternKind::kWhite});
        order.push_back({proto::PatternKind::kBlack});
    }
    return order;
}

// A vpe scan folder with the images in the tool's order.
inline void writeSyntheticScan(const SyntheticGrayCode& capture,
                               const std::filesystem::path& folder) {
    std::filesystem::create_directories(folder);
    std::mt19937 random(capture.seed);
    proto::ScanManifest manifest;
    manifest.patterns = capture.patterns;
    manifest.camera = {capture.cameraWidth, capture.cameraHeight, 8, 0, 0, "synthetic"};
    manifest.createdBy = "synthetic_gray_code.h";
    const std::vector<proto::PatternSpec> order = toolOrder(capture.patterns);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::string file = proto::scanImageName(i, order[i]);
        proto::writePnmAtomically(folder / file, capture.cameraWidth, capture.cameraHeight, 1,
                                  photographPattern(capture, order[i], random));
        manifest.images.push_back({file, order[i].name(), 1});
    }
    proto::writeScanManifest(folder, manifest);
}

// procam-calibration's capture folder: graycode_00.png … in the tool's order, with white and
// black.
inline void writeToolCapture(const SyntheticGrayCode& capture,
                             const std::filesystem::path& folder) {
    std::filesystem::create_directories(folder);
    std::mt19937 random(capture.seed);
    const std::vector<proto::PatternSpec> order = toolOrder(capture.patterns);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const std::string name =
            "graycode_" + std::string(i < 10 ? "0" : "") + std::to_string(i) + ".png";
        image::writeImage8(folder / name, capture.cameraWidth, capture.cameraHeight, 1,
                           photographPattern(capture, order[i], random));
    }
}

// A procam-calibration capture folder's graycode_NN.png rewritten into `to` as
// graycode_NN`extension`: 16-bit (level v of 255 as 257·v of 65535: the same value on the 0..1
// scale) or 8-bit; a JPEG at `jpegQuality`.
inline void convertToolCapture(const std::filesystem::path& from, const std::filesystem::path& to,
                               const std::string& extension, int bits, int jpegQuality = 90) {
    std::filesystem::create_directories(to);
    for (const auto& entry : std::filesystem::directory_iterator(from)) {
        if (entry.path().extension() != ".png") {
            continue;
        }
        auto input = OIIO::ImageInput::open(entry.path().string());
        if (!input) {
            throw std::runtime_error("cannot read " + entry.path().string());
        }
        const OIIO::ImageSpec& in = input->spec();
        std::vector<std::uint16_t> pixels(static_cast<std::size_t>(in.width) * in.height *
                                          in.nchannels);
        if (!input->read_image(0, 0, 0, in.nchannels, OIIO::TypeDesc::UINT16, pixels.data())) {
            throw std::runtime_error("cannot decode " + entry.path().string());
        }
        OIIO::ImageSpec spec(in.width, in.height, in.nchannels,
                             bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
        if (extension == ".jpg" || extension == ".jpeg") {
            spec.attribute("Compression", "jpeg:" + std::to_string(jpegQuality));
        }
        const std::string path = (to / entry.path().stem()).string() + extension;
        auto output = OIIO::ImageOutput::create(path);
        if (!output || !output->open(path, spec) ||
            !output->write_image(OIIO::TypeDesc::UINT16, pixels.data()) || !output->close()) {
            throw std::runtime_error("cannot write " + path);
        }
    }
}

}  // namespace vpe::testing
