// SPDX-License-Identifier: MIT
// GeometryBuffer: trace, pack and upload the projector pixels' geometry (see the header).
#include "geometry_buffer.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <vector>

#include <GLES3/gl31.h>

#include "vpe/proto/detail_normal.h"
#include "vpe/renderer/cpu/parallel_rows.h"

#include "shading_glsl.h"
#include "texture_formats.h"
#include "tile_cover.h"

namespace vpe::renderer::gles {

namespace {

// Rows traced, packed and uploaded at a time: bounds the CPU's copy (64 rows of 1920 pixels:
// 2.5 MB) while keeping the threads busy.
constexpr int kBandRows = 64;

}  // namespace

PackedPixel packProjectorPixel(const std::optional<ProjectorPixel>& pixel) {
    PackedPixel packed;
    if (!pixel) {
        return packed;
    }
    const SurfacePoint& point = pixel->point;
    packed.geometry0 = {
        static_cast<float>(point.position.x), static_cast<float>(point.position.y),
        static_cast<float>(point.position.z),
        // s/S, finite however grazing (0 · ∞ would be NaN in the shader); 0 where the share
        // asks nothing of this projector.
        pixel->share <= 0 ? 0.0f
        : pixel->irradianceScale > 0
            ? std::min(static_cast<float>(pixel->share / pixel->irradianceScale), kNoProjectorLight)
            : kNoProjectorLight};
    packed.geometry1 = {std::bit_cast<std::uint32_t>(static_cast<float>(point.normal.x)),
                        std::bit_cast<std::uint32_t>(static_cast<float>(point.normal.y)),
                        std::bit_cast<std::uint32_t>(static_cast<float>(point.normal.z)),
                        encodeOctahedralNormal(point.geometricNormal)};
    // The renderer's uv has v up (OBJ / GL); the textures are uploaded rows from the top.
    packed.uv = {static_cast<float>(point.uv.x), static_cast<float>(1.0 - point.uv.y)};
    const proto::TangentFrame<double> frame =
        proto::tangentFrame(point.normal, point.tangentU, point.tangentV);
    packed.tangents = {encodeOctahedralNormal(frame.t), encodeOctahedralNormal(frame.b)};
    return packed;
}

GeometryBuffer::GeometryBuffer(const ProjectorPixels& pixels, int threads, bool relief)
    : width_(pixels.width()), height_(pixels.height()), relief_(relief) {
    geometry0_ = makeTexture2D(kGeometry0Format, width_, height_, GL_RGBA, GL_FLOAT, nullptr);
    geometry1_ =
        makeTexture2D(kGeometry1Format, width_, height_, GL_RGBA_INTEGER, GL_UNSIGNED_INT, nullptr);
    uv_ = makeTexture2D(kUvFormat, width_, height_, GL_RG, GL_FLOAT, nullptr);
    if (relief_) {
        tracedGeometry1_ =
            makeTexture2D(GL_RGBA32UI, width_, height_, GL_RGBA_INTEGER, GL_UNSIGNED_INT, nullptr);
        tangents_ =
            makeTexture2D(GL_RG32UI, width_, height_, GL_RG_INTEGER, GL_UNSIGNED_INT, nullptr);
    }
    const auto w = static_cast<std::size_t>(width_);
    std::vector<float> geometry0(w * kBandRows * 4);
    std::vector<std::uint32_t> geometry1(w * kBandRows * 4);
    std::vector<float> uv(w * kBandRows * 2);
    std::vector<std::uint32_t> tangents(relief_ ? w * kBandRows * 2 : 0);
    std::atomic<std::size_t> covered{0};
    const int tilesX = (width_ + kTileSize - 1) / kTileSize;
    coveredTiles_.assign(static_cast<std::size_t>(tilesX) *
                             static_cast<std::size_t>((height_ + kTileSize - 1) / kTileSize),
                         0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    std::array<double, 3> low{HUGE_VAL, HUGE_VAL, HUGE_VAL}, high{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int first = 0; first < height_; first += kBandRows) {
        const int rows = std::min(kBandRows, height_ - first);
        forEachRow(rows, threads, [&](int row) {
            std::size_t hits = 0;
            for (int x = 0; x < width_; ++x) {
                const std::optional<ProjectorPixel> pixel = pixels.trace(x, first + row);
                hits += pixel ? 1 : 0;
                const PackedPixel packed = packProjectorPixel(pixel);
                const std::size_t i =
                    static_cast<std::size_t>(row) * w + static_cast<std::size_t>(x);
                std::copy(packed.geometry0.begin(), packed.geometry0.end(),
                          geometry0.begin() + 4 * i);
                std::copy(packed.geometry1.begin(), packed.geometry1.end(),
                          geometry1.begin() + 4 * i);
                uv[2 * i] = packed.uv[0];
                uv[2 * i + 1] = packed.uv[1];
                if (relief_) {
                    tangents[2 * i] = packed.tangents[0];
                    tangents[2 * i + 1] = packed.tangents[1];
                }
            }
            covered += hits;
        });
        for (int row = 0; row < rows; ++row) {
            for (int x = 0; x < width_; ++x) {
                if (geometry0[(static_cast<std::size_t>(row) * w + static_cast<std::size_t>(x)) *
                                  4 +
                              3] >= 0) {
                    const float* position = &geometry0[(static_cast<std::size_t>(row) * w +
                                                        static_cast<std::size_t>(x)) *
                                                       4];
                    for (std::size_t k = 0; k < 3; ++k) {
                        low[k] = std::min(low[k], static_cast<double>(position[k]));
                        high[k] = std::max(high[k], static_cast<double>(position[k]));
                    }
                    coveredTiles_[static_cast<std::size_t>(((first + row) / kTileSize) * tilesX +
                                                           x / kTileSize)] = 1;
                }
            }
        }
        glBindTexture(GL_TEXTURE_2D, geometry0_.get());
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, width_, rows, GL_RGBA, GL_FLOAT,
                        geometry0.data());
        glBindTexture(GL_TEXTURE_2D, geometry1_.get());
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, width_, rows, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                        geometry1.data());
        glBindTexture(GL_TEXTURE_2D, uv_.get());
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, width_, rows, GL_RG, GL_FLOAT, uv.data());
        if (relief_) {
            glBindTexture(GL_TEXTURE_2D, tracedGeometry1_.get());
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, width_, rows, GL_RGBA_INTEGER,
                            GL_UNSIGNED_INT, geometry1.data());
            glBindTexture(GL_TEXTURE_2D, tangents_.get());
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, first, width_, rows, GL_RG_INTEGER,
                            GL_UNSIGNED_INT, tangents.data());
        }
    }
    covered_ = covered;
    if (covered_ > 0) {
        cube_.side = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            cube_.low[k] = low[k];
            cube_.side = std::max(cube_.side, high[k] - low[k]);
        }
        cube_.side = cube_.side > 0 ? cube_.side : 1.0;  // a single point
    }
    checkGlError("uploading the projector's geometry buffer");
}

}  // namespace vpe::renderer::gles
