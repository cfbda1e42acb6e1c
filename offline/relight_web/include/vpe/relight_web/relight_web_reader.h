// SPDX-License-Identifier: MIT
// RelightWebReader: reads a Relight web RTI (info.json and plane_N.jpg) of the bilinear, mrgb
// kind and relights it for any light direction the way OpenLIME's shader does.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/relight_web/bilinear_light_grid.h"

namespace vpe::relight_web {

class RelightWebReader {
public:
    // `path` is the export's folder or its info.json. Throws common::InputError naming the file and
    // what is wrong with it (other bases and colour spaces are refused, not misread).
    explicit RelightWebReader(const std::filesystem::path& path);

    int width() const { return width_; }
    int height() const { return height_; }
    int planes() const { return planes_; }
    int resolution() const { return grid_.resolution(); }
    // info.json's "lights": the capture's light directions, if the export records them.
    const std::vector<proto::Vec3d>& lights() const { return lights_; }

    // What OpenLIME's shader computes for the light towards `towardsLight` before anything
    // is displayed (ShaderRTI's mrgb render()): width·height·3 interleaved, unclamped — it
    // can fall below 0 or rise above 1. openlime_display.h shows it as a browser does.
    std::vector<float> decode(const proto::Vec3d& towardsLight) const;
    // The same at grid node `node` exactly (the light of grid().nodeDirection(node)): the
    // values every light between the nodes interpolates, with non-negative weights.
    std::vector<float> decodeNode(int node) const;
    // The decoded values clamped to [0, 1]: the picture with no display step in between.
    std::vector<float> relight(const proto::Vec3d& towardsLight) const;

    const BilinearLightGrid& grid() const { return grid_; }

private:
    std::vector<float> decode(const LightGridWeights& weights) const;

    int width_ = 0;
    int height_ = 0;
    int planes_ = 0;
    BilinearLightGrid grid_;
    std::vector<proto::Vec3d> lights_;
    std::vector<float> basis_;         // decoded: (planes + 1) · R² · 3, OpenLIME's layout
    std::vector<float> coefficients_;  // decoded: per pixel, `planes_` values
};

// The light directions a Relight export's info.json records ("lights", flat x, y, z triples),
// normalized; empty when it has none. Throws common::InputError naming the file.
std::vector<proto::Vec3d> readRelightExportLights(const std::filesystem::path& infoJson);

}  // namespace vpe::relight_web
