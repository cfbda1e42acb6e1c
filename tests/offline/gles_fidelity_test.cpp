// SPDX-License-Identifier: MIT
// What the device shows against the exact material: a synthetic capture fitted and baked as
// `vpe bake` does by default (low-rank rank 12, θs basis K = 4), rendered by the GLES renderer
// (headless) and by the CPU reference with the full-precision coefficients under the reference
// lights, two of them grazing and one behind the vase. The loss is the θs basis's, the half
// floats' and the table's together. SKIPs without EGL.
#include <algorithm>
#include <iostream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "vpe/proto/bundle.h"

#include "renderer/gles_test_platform.h"
#include "support/command_runner.h"
#include "support/fitted_capture.h"
#include "support/gpu_fidelity.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

// The shared headless platform; SKIPs without EGL.
class GlesFidelity : public renderer::testing::GlesTest {};

TEST_F(GlesFidelity, DeviceFramesStayWithinTheBudgetOfTheExactModel) {
    const testing::TemporaryFolder folder;
    const std::string capture = (folder / "capture").string();
    const std::string model = (folder / "model.exr").string();
    const std::string bundle = (folder / "scene.vpeb").string();
    ASSERT_NO_FATAL_FAILURE(testing::synthesizeAndFit(capture, model, 64));
    const testing::CommandResult baked =
        runCommand(vpe({"bake", "--texture", model, "--out", bundle}));
    ASSERT_EQ(baked.exitStatus, 0) << baked.err;
    const proto::BundleFile file = proto::BundleFile::open(bundle);
    ASSERT_EQ(file->model().thetaBasisSize(), 4);
    platform()->makeCurrent();
    double worstObject = std::numeric_limits<double>::infinity(), worstFrame = worstObject;
    for (const testing::GpuFidelity& light :
         testing::measureGpuFidelity(file.view(), *platform())) {
        std::cout << light.light << ": gain " << light.gain << ", " << light.covered
                  << " pixels on the vase, " << light.psnrObject << " dB on it, " << light.psnrFrame
                  << " dB over the frame, largest difference " << light.largest << " levels\n";
        worstObject = std::min(worstObject, light.psnrObject);
        worstFrame = std::min(worstFrame, light.psnrFrame);
    }
    // Measured 49.0 dB on the vase and 58.7 dB over the frame (the front light, at gain 1; 49.1
    // before the shading geometry was stored in half floats and the response became a table; the
    // bundle carries the fit's relief, folded into the geometry by the relief pass):
    // this 64² fit of a noisy capture, mapped unquilted, is harder for K = 4 than the demo's
    // quilted texture (52.3 and 62.0 dB, vpe_gles_fidelity in demo-output/summary.txt).
    EXPECT_GE(worstObject, 48.5);
    EXPECT_GE(worstFrame, 58.0);

    // The same model drawn for a viewing zone of 8 visitors around the vase (bundle 1.6): the
    // load passes' per-pixel eye (vpeZoneViewer) against proto::zoneEye in the CPU reference.
    // Measured 45.1 dB (front light) … 57.5: the eyes at the vase's sides put highlights where
    // the one front eye saw none, and the θs basis (K = 4) approximates more of them; the eye
    // itself agrees pixel for pixel (GlesLoadPassesTest.ShadingGeometryPacksTheTracedPixels).
    const std::string zoned = (folder / "zone.vpeb").string();
    const testing::CommandResult bakedZone =
        runCommand(vpe({"bake", "--texture", model, "--viewing-zone", "8", "--out", zoned}));
    ASSERT_EQ(bakedZone.exitStatus, 0) << bakedZone.err;
    const proto::BundleFile zoneFile = proto::BundleFile::open(zoned);
    ASSERT_EQ(zoneFile->settings().viewingZone.size(), 8u);
    double worstZone = std::numeric_limits<double>::infinity();
    for (const testing::GpuFidelity& light :
         testing::measureGpuFidelity(zoneFile.view(), *platform())) {
        std::cout << "zone, " << light.light << ": " << light.psnrObject << " dB on the vase\n";
        worstZone = std::min(worstZone, light.psnrObject);
    }
    EXPECT_GE(worstZone, 44.5);
}

}  // namespace
}  // namespace vpe
