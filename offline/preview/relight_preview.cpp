// SPDX-License-Identifier: MIT
// Relit preview tiles.
#include "vpe/preview/relight_preview.h"

#include <algorithm>
#include <cmath>

#include "vpe/image/image_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/srgb.h"

namespace vpe::preview {

const std::vector<proto::Vec3d>& RelightPreview::lights() {
    // Head-on, then three lights 45° up at azimuths 0°, 120° and 240°.
    static const std::vector<proto::Vec3d> kLights = [] {
        std::vector<proto::Vec3d> lights{{0, 0, 1}};
        const double c = std::cos(M_PI / 4);
        for (int i = 0; i < 3; ++i) {
            const double azimuth = i * 2 * M_PI / 3;
            lights.push_back({c * std::cos(azimuth), c * std::sin(azimuth), std::sin(M_PI / 4)});
        }
        return lights;
    }();
    return kLights;
}

RelightPreview::RelightPreview(int width, int height, int harmonics) : harmonics_(harmonics) {
    step_ = std::max(1, (std::max(width, height) + kMaxTile - 1) / kMaxTile);
    tileWidth_ = (width + step_ - 1) / step_;
    tileHeight_ = (height + step_ - 1) / step_;
    pixels_.assign(static_cast<std::size_t>(tileWidth_) * lights().size() * tileHeight_ * 3, 0);
}

void RelightPreview::addRows(int rowBegin, const model::ModelRows& rows) {
    const proto::Vec3d view{0, 0, 1};
    const std::size_t stride = static_cast<std::size_t>(tileWidth_) * lights().size() * 3;
    for (int r = 0; r < rows.rows; ++r) {
        const int y = rowBegin + r;
        if (y % step_ != 0) {
            continue;
        }
        for (int x = 0; x < rows.width; x += step_) {
            if (!rows.valid[rows.pixel(r, x)]) {
                continue;
            }
            const float* n = &rows.normal[rows.pixel(r, x) * 3];
            const proto::Vec3d normal{n[0], n[1], n[2]};
            for (std::size_t l = 0; l < lights().size(); ++l) {
                const auto angles = proto::reflectionAngles(normal, lights()[l], view);
                std::uint8_t* out = pixels_.data() + static_cast<std::size_t>(y / step_) * stride +
                                    (l * tileWidth_ + static_cast<std::size_t>(x / step_)) * 3;
                for (int c = 0; c < 3; ++c) {
                    const double value =
                        proto::evaluateFourierBrdf(rows.coefficientsAt(r, x, c), harmonics_,
                                                   angles.cosThetaD, angles.cosThetaS);
                    const double encoded = proto::linearToSrgb(std::clamp(value, 0.0, 1.0));
                    out[c] = static_cast<std::uint8_t>(std::lround(encoded * 255));
                }
            }
        }
    }
}

void RelightPreview::write(const std::filesystem::path& path) const {
    image::writeImage8(path, tileWidth_ * static_cast<int>(lights().size()), tileHeight_, 3,
                       pixels_);
}

}  // namespace vpe::preview
