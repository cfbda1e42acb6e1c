// SPDX-License-Identifier: MIT
// ProcamSimulator: what a camera records of any projector image on a simulated installation,
// and the truth the measurements are checked against. Everything that does not depend on the
// image — the ray of every camera sample, the surface it meets, where that point falls in the
// projector, how much of the projector's light reaches it, the interreflection's form factors —
// is traced once with the CPU reference's ray caster; an image then costs a blur and a
// weighted sum per camera pixel.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "vpe/proto/luminance.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::renderer::procam {

// What the camera wrote: width·height·channels samples in [0, 2^bits − 1], rows from the top.
struct CameraFrame {
    int width = 0, height = 0, channels = 1, bits = 8;
    std::vector<std::uint16_t> samples;

    int maxValue() const { return (1 << bits) - 1; }
};

// The truth for every camera pixel: the projector coordinate it sees (pixels, distortion
// applied) — the mean over the pixel's area of the coordinates of the points the projector
// lights there, weighted by the light each sends to the camera (the samples the image is
// rendered with), which is what an ideal decoder reports for a pixel that sees several projector
// pixels, as at a grazing angle; NaN where the projector lights nothing the pixel sees. The same
// for the pixel's centre ray alone (centreX, centreY), and the point that ray meets, in the
// camera's frame (metres).
struct CameraTruth {
    std::vector<float> projectorX, projectorY;  // width·height each
    std::vector<float> centreX, centreY;        // width·height each
    std::vector<float> pointCamera;             // width·height·3, NaN off the object
};

// The truth for every projector pixel's centre ray: the object point it lights and the normal
// there, in the camera's frame (NaN where the ray misses the object or the board intercepts
// it), and whether the camera sees that point (in its image, in front, not occluded, facing it).
struct ProjectorTruth {
    int width = 0, height = 0;
    std::vector<float> position, normal;  // width·height·3
    std::vector<std::uint8_t> seen;       // width·height, 1 where the camera sees the point
};

class ProcamSimulator {
public:
    // Traces the camera's samples (threads ≤ 0: all cores). Throws std::invalid_argument
    // naming what checkProcamScene or checkSimulatedCamera refuse.
    ProcamSimulator(const ProcamScene& scene, const SimulatedCamera& camera, int threads = 0);
    ~ProcamSimulator();
    ProcamSimulator(const ProcamSimulator&) = delete;
    ProcamSimulator& operator=(const ProcamSimulator&) = delete;

    const ProcamScene& scene() const;
    const SimulatedCamera& camera() const;

    // The linear radiance on every camera pixel (RGB, averaged over its samples) when the
    // projector shows `levels`: drive levels in [0, 1], three per projector pixel, rows from the
    // top. Each level's time-average: what an exposure of whole frames sees. Throws
    // std::invalid_argument for a size that is not the projector's.
    RgbImage radiance(const RgbImage& levels) const;
    // What capture `frame` integrates: with the projector's DLP timing on, its bit-planes over
    // the frame's exposure window (its start deterministic in the camera's seed and `frame`, as
    // the sensor's noise); with it off, the time-average above.
    RgbImage radiance(const RgbImage& levels, std::uint64_t frame) const;
    // The same for 8-bit codes shown on all three channels (the scan's patterns).
    RgbImage radiance(std::span<const std::uint8_t> grayCodes) const;
    RgbImage radiance(std::span<const std::uint8_t> grayCodes, std::uint64_t frame) const;

    // The sensor: exposure, shot and read noise (deterministic in the camera's seed and
    // `frame`), response, quantization.
    CameraFrame expose(const RgbImage& radiance, std::uint64_t frame) const;
    // The same through another sensor on the same optics: `sensor`'s exposure, noise, response,
    // bits and colour (its geometry must be the simulator camera's size). The radiometric
    // capture photographs in colour and brackets exposures with the camera that scanned in
    // monochrome. Throws std::invalid_argument for a sensor checkSimulatedCamera refuses.
    CameraFrame expose(const RgbImage& radiance, std::uint64_t frame,
                       const SimulatedCamera& sensor) const;

    CameraTruth cameraTruth() const;
    ProjectorTruth projectorTruth() const;

private:
    RgbImage radianceAt(const RgbImage& levels, std::optional<double> windowStart) const;
    static RgbImage levelsOf(const proto::PinholeCamera& projector,
                             std::span<const std::uint8_t> grayCodes);

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

using proto::luminance709;

}  // namespace vpe::renderer::procam
