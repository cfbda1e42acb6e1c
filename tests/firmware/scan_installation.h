// SPDX-License-Identifier: MIT
// A small simulated installation for the scan tests: a plaster ball in front of a wall (one
// OBJ), a 320 × 180 projector and a 320 × 240 camera beside it, written as a scene file
// (renderer/procam's writeSceneFile, what vpe synth-procam writes) and a headless board whose
// [scan] simulates its camera.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::firmware::testing {

struct ScanInstallation {
    std::filesystem::path sceneFile;  // folder/installation.toml (and folder/ball-wall.obj)
    renderer::procam::ProcamScene scene;
    renderer::procam::SimulatedCamera camera;
};

// Writes the OBJ and the scene file into `folder` (which must exist). `bits`: 8 or 10;
// `response`: the camera's (linear, or a 2.2 gamma as an ISP's output).
ScanInstallation writeScanInstallation(
    const std::filesystem::path& folder, int bits = 8,
    renderer::procam::CameraResponse response = renderer::procam::CameraResponse::kLinear);

// What a manifest vpe-player --scan wrote of this installation (the scan's or the radiometric
// capture's) says of its maker, its camera and its frames: vpe-player, the simulated 320 × 240
// 8-bit camera of the scene file, frames (the patterns or the flat fields) the projector's
// 320 × 180, and no projector latency (the tests' boards set latency_ms = 0).
template <typename Manifest, typename Frames>
void expectWrittenBySimulatedPlayer(const Manifest& manifest, const Frames& frames,
                                    const ScanInstallation& installation) {
    EXPECT_EQ(manifest.createdBy, "vpe-player");
    EXPECT_EQ(frames.width, 320);
    EXPECT_EQ(frames.height, 180);
    EXPECT_EQ(manifest.camera.width, 320);
    EXPECT_EQ(manifest.camera.height, 240);
    EXPECT_EQ(manifest.camera.bits, 8);
    EXPECT_EQ(manifest.camera.source, "simulated:" + installation.sceneFile.string());
    EXPECT_EQ(manifest.projectorLatencyMs, 0.0);
}

// The OBJ's text: a UV sphere of `radius` about (0, radius, 0) on a wall at z = −wallDistance.
std::string ballAndWallObj(double radius, double wallDistance);

}  // namespace vpe::firmware::testing
