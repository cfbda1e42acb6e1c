// SPDX-License-Identifier: MIT
// Kernel input setup.
#include "vpe/fit/chunk_setup.h"

namespace vpe::fit {

std::vector<KernelLight> kernelLights(const capture::Capture& capture) {
    std::vector<KernelLight> lights;
    lights.reserve(capture.images.size());
    for (const capture::CaptureImage& image : capture.images) {
        lights.push_back({static_cast<float>(image.light.x), static_cast<float>(image.light.y),
                          static_cast<float>(image.light.z),
                          static_cast<float>(1.0 / image.intensity)});
    }
    return lights;
}

KernelLightSet kernelLightSet(const capture::Capture& capture,
                              const std::vector<KernelLight>& lights) {
    KernelLightSet set;
    set.lights = lights.data();
    set.count = static_cast<int>(lights.size());
    set.point = capture.lightKind == capture::LightKind::kPoint;
    set.referenceDistanceSquared =
        static_cast<float>(capture.lightReferenceDistance * capture.lightReferenceDistance);
    return set;
}

void fillChunkLane(const capture::SurfaceGeometry& geometry, const normals::NormalMap& normals,
                   int x, int y, int lane, ChunkGeometry& chunk, bool& laneValid) {
    const bool inside = x >= 0 && x < geometry.width();
    laneValid = inside && normals.validAt(x, y);
    proto::Vec3d n{0, 0, 1}, v{0, 0, 1}, p{0, 0, 0};
    if (inside) {
        v = geometry.toViewer(x, y);
        p = geometry.position(x, y);
        if (laneValid) {
            n = normals.at(x, y);
        }
    }
    chunk.normal[0][lane] = static_cast<float>(n.x);
    chunk.normal[1][lane] = static_cast<float>(n.y);
    chunk.normal[2][lane] = static_cast<float>(n.z);
    chunk.view[0][lane] = static_cast<float>(v.x);
    chunk.view[1][lane] = static_cast<float>(v.y);
    chunk.view[2][lane] = static_cast<float>(v.z);
    chunk.position[0][lane] = static_cast<float>(p.x);
    chunk.position[1][lane] = static_cast<float>(p.y);
    chunk.position[2][lane] = static_cast<float>(p.z);
}

void fillChunkGeometry(const capture::SurfaceGeometry& geometry, const normals::NormalMap& normals,
                       int x0, int y, ChunkGeometry& chunk, bool (&laneValid)[kLanes]) {
    for (int lane = 0; lane < kLanes; ++lane) {
        const int x = x0 + lane < geometry.width() ? x0 + lane : -1;
        fillChunkLane(geometry, normals, x, y, lane, chunk, laneValid[lane]);
    }
}

ChunkObservations chunkObservations(const capture::SampleBand& band, int row, int x0) {
    ChunkObservations observations;
    static_assert(capture::SampleBand::kChunkWidth == kLanes, "a band chunk is one kernel vector");
    observations.values = band.values.data() + band.valueIndex(0, 0, row, x0);
    observations.sampleStride = static_cast<std::size_t>(capture::SampleBand::kChannels) * kLanes;
    observations.channelStride = kLanes;
    observations.weights = band.fullyUsable[band.chunk(row, x0)]
                               ? nullptr
                               : band.weights.data() + band.sampleIndex(0, row, x0);
    observations.weightStride = kLanes;
    return observations;
}

}  // namespace vpe::fit
