// SPDX-License-Identifier: MIT
// Completing the measured light's maps over the bundle's mesh (see the header).
#include "vpe/bake/measured_light_maps.h"

#include <cmath>
#include <vector>

#include "vpe/bake/bundle_render_mesh.h"
#include "vpe/common/input_error.h"
#include "vpe/common/quantile.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/projector_pixels.h"

namespace vpe::bake {

MeasuredLightBake bakeMeasuredLight(const radiometry::ProjectorRadiometry& measured,
                                    const BundleMesh& mesh,
                                    const proto::ProjectorCalibration& projector,
                                    const std::filesystem::path& source) {
    const int width = static_cast<int>(projector.width),
              height = static_cast<int>(projector.height);
    if (measured.width != width || measured.height != height) {
        throw common::InputError(source, "maps of " + std::to_string(measured.width) + "x" +
                                             std::to_string(measured.height) +
                                             ", the projector is " + std::to_string(width) + "x" +
                                             std::to_string(height));
    }
    renderer::ProjectorModel model;
    model.camera = proto::cameraOf(projector);
    const BundleRenderMesh renderMesh(mesh);
    const renderer::ProjectorPixels pixels(renderMesh.view, model);

    const std::size_t count = static_cast<std::size_t>(width) * height;
    std::vector<float> geometry(count, 0);
    // Per pixel: 0 not covered, 1 covered and known, 2 covered and still unknown.
    std::vector<std::uint8_t> state(count, 0);
    std::vector<float> albedo(3 * count, 0), floor(3 * count, 0);
    MeasuredLightBake out;
    std::vector<double> albedos[3], floors[3];
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * width + x;
            const auto traced = pixels.trace(x, y);
            if (!traced || !(traced->irradianceScale > 0)) {
                continue;
            }
            ++out.covered;
            geometry[p] = static_cast<float>(traced->irradianceScale);
            const float* f = &measured.irradiance[3 * p];
            if (std::isnan(f[0]) || std::isnan(f[1]) || std::isnan(f[2])) {
                state[p] = 2;
                continue;
            }
            state[p] = 1;
            ++out.measured;
            for (std::size_t c = 0; c < 3; ++c) {
                albedo[3 * p + c] = f[c] / geometry[p];
                floor[3 * p + c] = std::max(0.0f, measured.floor[3 * p + c]);
                albedos[c].push_back(double(albedo[3 * p + c]));
                floors[c].push_back(double(floor[3 * p + c]));
            }
        }
    }
    if (out.measured == 0) {
        throw common::InputError(source,
                                 "no measured pixel falls on the bundle's mesh: is it the "
                                 "scan's installation?");
    }
    // Grow the known values into the unknown covered pixels, one ring a pass: each takes the
    // mean of its known 8-neighbours.
    std::vector<std::size_t> frontier;
    for (bool grew = true; grew;) {
        grew = false;
        frontier.clear();
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * width + x;
                if (state[p] != 2) {
                    continue;
                }
                double a[3] = {0, 0, 0}, d[3] = {0, 0, 0};
                int known = 0;
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= width || ny >= height) {
                            continue;
                        }
                        const std::size_t q = static_cast<std::size_t>(ny) * width + nx;
                        if (state[q] != 1) {
                            continue;
                        }
                        ++known;
                        for (std::size_t c = 0; c < 3; ++c) {
                            a[c] += double(albedo[3 * q + c]);
                            d[c] += double(floor[3 * q + c]);
                        }
                    }
                }
                if (known > 0) {
                    for (std::size_t c = 0; c < 3; ++c) {
                        albedo[3 * p + c] = static_cast<float>(a[c] / known);
                        floor[3 * p + c] = static_cast<float>(d[c] / known);
                    }
                    frontier.push_back(p);
                }
            }
        }
        for (const std::size_t p : frontier) {
            state[p] = 1;
            ++out.completed;
            grew = true;
        }
    }
    // Islands no measurement reaches: the object's typical albedo and floor.
    for (std::size_t p = 0; p < count; ++p) {
        if (state[p] == 2) {
            for (std::size_t c = 0; c < 3; ++c) {
                albedo[3 * p + c] = static_cast<float>(common::quantile(albedos[c], 0.5));
                floor[3 * p + c] = static_cast<float>(common::quantile(floors[c], 0.5));
            }
            ++out.completed;
        }
    }
    out.radiometry.mixing = measured.mixing;
    out.radiometry.irradiance.assign(3 * count, 0);
    out.radiometry.floor.assign(3 * count, 0);
    for (std::size_t p = 0; p < count; ++p) {
        if (state[p] == 0) {
            continue;
        }
        const bool known = !std::isnan(measured.irradiance[3 * p]);
        for (std::size_t c = 0; c < 3; ++c) {
            out.radiometry.irradiance[3 * p + c] =
                known ? std::max(0.0f, measured.irradiance[3 * p + c])
                      : albedo[3 * p + c] * geometry[p];
            out.radiometry.floor[3 * p + c] = floor[3 * p + c];
        }
    }
    return out;
}

}  // namespace vpe::bake
