// SPDX-License-Identifier: MIT
// GlesFrameRenderer's frame against the CPU reference (renderProjectorFrame, quantized to
// 8 bits) for several lights, viewers, both presets and both response kinds. The test bundles
// carry no θs basis, so the GPU evaluates every harmonic through the θs table (2M + 1
// functions): what differs is the half-float material and table, the table's interpolation,
// the half-float shading geometry (position about the centre, n, the mirrored viewer), the
// response table and float arithmetic. Thresholds sit ~0.5–1 dB under the measured values.
// On failure the actual, expected and difference images are written beside the test output
// (the working directory): PNG, or PPM in the device-only build (failure_image.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"

#include "failure_image.h"
#include "gles_test_bundle.h"
#include "gles_test_platform.h"

namespace vpe::renderer::testing {
namespace {

struct FrameCase {
    std::string name;
    std::array<float, 3> light;
    std::array<float, 3> viewer;
    std::string preset;
    bool inverseSquare = false;
    float gain = 1.0f;
    bool liveWeights = false;
    // Rendered first, then `preset` selected (at once): what a preset change leaves behind.
    std::string before{};
};

class GlesFrameTest : public GlesTest {
protected:
    // Returns the PSNR (dB) of the GPU frame against the quantized CPU frame.
    double comparePsnr(const GlesBundleSpec& spec, const FrameCase& frame) {
        MappedTestBundle bundle(spec);
        gles::GlesRendererOptions options;
        options.viewer = frame.viewer;
        options.liveWeights = frame.liveWeights;
        gles::GlesFrameRenderer renderer(bundle.view(), options);
        std::unique_ptr<gles::RenderTarget> target =
            platform()->createRenderTarget(renderer.width(), renderer.height());
        gles::FrameInputs inputs;
        inputs.lightPosition = frame.light;
        inputs.inverseSquare = frame.inverseSquare;
        inputs.referenceDistance = 0.5f;
        inputs.gain = frame.gain;
        if (!frame.before.empty()) {
            renderer.selectPreset(frame.before);
            renderer.render(*target, inputs);
        }
        renderer.selectPreset(frame.preset, false);
        renderer.render(*target, inputs);
        target->present();
        const std::vector<std::uint8_t> rgba = target->readRgba8();

        BundleScene scene(bundle.view(), frame.preset);
        VirtualLight light;
        light.position = {frame.light[0], frame.light[1], frame.light[2]};
        light.inverseSquare = frame.inverseSquare;
        light.referenceDistance = 0.5;
        RenderOptions reference_options;
        reference_options.gain = static_cast<double>(frame.gain);
        const ProjectorFrame reference = renderProjectorFrame(
            scene.scene(light, {frame.viewer[0], frame.viewer[1], frame.viewer[2]}),
            reference_options);

        const int w = renderer.width(), h = renderer.height();
        const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
        std::vector<std::uint8_t> actual(pixels * 3), expected(pixels * 3), difference(pixels * 3);
        double squared = 0;
        std::size_t covered = 0, differing = 0;
        largeDifferences_ = 0;
        int largest = 0;
        for (std::size_t p = 0; p < pixels; ++p) {
            covered += reference.coverage.values[p] != 0 ? 1 : 0;
            bool differs = false;
            int pixelLargest = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                const double level = reference.level.values[3 * p + c];
                const auto want =
                    static_cast<int>(std::lround(std::clamp(level, 0.0, 1.0) * 255.0));
                const int got = rgba[4 * p + c];
                actual[3 * p + c] = static_cast<std::uint8_t>(got);
                expected[3 * p + c] = static_cast<std::uint8_t>(want);
                const int delta = std::abs(got - want);
                difference[3 * p + c] = static_cast<std::uint8_t>(std::min(255, 16 * delta));
                squared += static_cast<double>(delta) * delta;
                largest = std::max(largest, delta);
                pixelLargest = std::max(pixelLargest, delta);
                differs = differs || delta != 0;
            }
            differing += differs ? 1 : 0;
            // Pixels that one renderer covers and the other does not, or shades otherwise. Not
            // those the reference clips: a projector at grazing incidence cannot deliver their
            // light, 1/S is huge there, and the material's code rounding tips them to either
            // end (a level of 0 or 255 is as wrong as the other).
            largeDifferences_ += pixelLargest > 16 && reference.clipped.values[p] == 0 ? 1 : 0;
        }
        const double mse = squared / static_cast<double>(pixels * 3);
        const double psnr = mse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
        std::cout << frame.name << ": PSNR " << psnr << " dB, " << covered << " covered pixels, "
                  << differing << " differ (" << largeDifferences_ << " by more than 16 levels), "
                  << "largest difference " << largest << " levels\n";
        if (psnr < minimumPsnr_) {
            const std::string stem = "gles_frame_" + frame.name;
            ADD_FAILURE() << frame.name << ": wrote "
                          << writeFailureImage(stem + ".actual", w, h, actual) << ", "
                          << writeFailureImage(stem + ".expected", w, h, expected) << ", "
                          << writeFailureImage(stem + ".difference", w, h, difference);
        }
        EXPECT_GT(covered, pixels / 10) << "the test scene should cover the projector's view";
        return psnr;
    }
    // Of the last comparePsnr: pixels with a channel more than 16 levels off.
    std::size_t largeDifferences_ = 0;
    // Below it, comparePsnr writes the failure images.
    double minimumPsnr_ = 50.0;
};

// What each texture path must guarantee against the CPU reference, as 8-bit PSNR over the
// frame (its uncovered pixels black in both): 60.5 dB is an RMS error of 0.24 level. What each
// path loses to its precision: above all the material's codes (material_codes.h: u_j in signed
// bytes of one step per function, 1/127 of its largest weight; kd in 10 bits), then the shading
// geometry in half floats and the position in 10-bit steps of the object's cube, the response
// through its 4096-sample table; live weights: the regions' codes blended and rounded again;
// wrapping in u: the seam's footprint; relief: its tilted normal in half floats. These bundles
// are harsher than a fitted capture: every harmonic through the table (K = 2M + 1, each its own
// byte) and strongly coloured materials, where the demo bundle loses 0.1 dB to the codes
// (vpe_gles_fidelity: 51.1 dB on the vase at worst, 51.2 in half floats). A code's step is
// absolute, and near black the response inverse is steepest: a channel that should be dark can
// land up to 30 levels off in a few pixels (largeDifferences_, at most 3 of a frame here).
// The values in the messages were measured on x86-64 and on arm64 (llvmpipe, under qemu-user):
// they agree to 0.002 dB.
constexpr double kStaticPresetDb = 60.5;
constexpr double kCurveResponseDb = 61.5;
constexpr double kMeasuredLightDb = 60.0;
constexpr double kLiveWeightsDb = 57.5;
constexpr double kWrapUDb = 58.0;
constexpr double kReliefDb = 60.5;
constexpr double kReliefLiveDb = 59.5;
constexpr double kReliefWrapUDb = 58.0;
// A frame with many more of its pixels covered (long bent edges, 640 × 480), or with every one
// of M = 10's 21 functions coded: the same error a pixel, more of it.
constexpr double kLongEdgesDb = 53.5;
constexpr double kManyFunctionsDb = 54.5;
// Pixels more than 16 levels off that the reference does not clip (largeDifferences_): the
// codes' near-black pixels above; a coverage or seam error would put dozens there.
constexpr std::size_t kLargeDifferences = 3;

const std::vector<FrameCase>& frameCases() {
    static const std::vector<FrameCase> cases{
        {"front_stripes", {0.4f, 0.3f, 0.5f}, {0.3f, 0.2f, 0.6f}, "stripes"},
        {"front_radial", {0.4f, 0.3f, 0.5f}, {0.3f, 0.2f, 0.6f}, "radial"},
        {"left_stripes", {-0.3f, 0.2f, 0.4f}, {-0.2f, 0.1f, 0.7f}, "stripes"},
        {"above_radial_inverse_square", {0.0f, 0.5f, 0.3f}, {0.1f, 0.3f, 0.5f}, "radial", true},
        {"grazing_radial_gain", {0.6f, 0.05f, -0.1f}, {0.0f, 0.1f, 0.8f}, "radial", false, 0.6f},
    };
    return cases;
}

TEST_F(GlesFrameTest, MatchesCpuReferenceWithGammaResponse) {
    for (const FrameCase& frame : frameCases()) {
        EXPECT_GE(comparePsnr({}, frame), kStaticPresetDb)
            << frame.name << ": measured 61.04-67.13 dB";
    }
}

TEST_F(GlesFrameTest, MatchesCpuReferenceWithCurveResponse) {
    GlesBundleSpec spec;
    spec.curveResponse = true;
    for (const FrameCase& frame : {frameCases()[0], frameCases()[3]}) {
        EXPECT_GE(comparePsnr(spec, {frame.name + "_curve", frame.light, frame.viewer, frame.preset,
                                     frame.inverseSquare, frame.gain}),
                  kCurveResponseDb)
            << frame.name << ": measured 62.02, 62.93 dB";
    }
}

TEST_F(GlesFrameTest, MatchesCpuReferenceWithMeasuredLight) {
    GlesBundleSpec spec;
    spec.curveResponse = true;
    spec.measuredLight = true;
    for (const FrameCase& frame : {frameCases()[0], frameCases()[3], frameCases()[4]}) {
        EXPECT_GE(comparePsnr(spec, {frame.name + "_measured", frame.light, frame.viewer,
                                     frame.preset, frame.inverseSquare, frame.gain}),
                  kMeasuredLightDb)
            << frame.name << ": measured 60.79, 61.61, 65.85 dB";
        EXPECT_LE(largeDifferences_, kLargeDifferences);
    }
}

TEST_F(GlesFrameTest, MatchesCpuReferenceWithoutDistortionAndMoreHarmonics) {
    GlesBundleSpec spec;
    spec.distortion = false;
    spec.harmonics = 10;
    spec.lowRank = 6;
    spec.projectorWidth = 200;
    spec.projectorHeight = 150;
    EXPECT_GE(
        comparePsnr(spec, {"m10_undistorted", {0.2f, 0.4f, 0.5f}, {0.3f, 0.2f, 0.6f}, "stripes"}),
        kManyFunctionsDb)
        << "M = 10 (21 table functions, each its own byte): measured 54.91 dB";
    EXPECT_LE(largeDifferences_, kLargeDifferences);
}

// Long triangles under strong distortion: edges bend by pixels between their vertices. The GPU
// reads the CPU's own traced pixels (geometry buffer), so coverage and silhouettes agree by
// construction: no pixel is more than a few levels off.
TEST_F(GlesFrameTest, MatchesCpuReferenceWithLongBentEdges) {
    GlesBundleSpec spec;
    spec.projectorWidth = 640;
    spec.projectorHeight = 480;
    spec.distortionCoefficients = {1.2, 0.0, 0.002, -0.002, 0.0};  // monotone for r < 0.52
    spec.vaseSegments = 6;
    spec.vaseRings = 3;
    EXPECT_GE(
        comparePsnr(spec, {"long_bent_edges", {0.4f, 0.3f, 0.5f}, {0.3f, 0.2f, 0.6f}, "radial"}),
        kLongEdgesDb)
        << "measured 54.03 dB";
    EXPECT_LE(largeDifferences_, kLargeDifferences);
}

// Textures that tile in u, with the seam u = 0 | 1 turned to the projector: the GPU's REPEAT
// sampling against the CPU reference's wrapping footprint, static and live weights. The seam's
// pixels do depend on the wrapping (the CPU frame clamping instead differs there), so the
// comparison covers them.
TEST_F(GlesFrameTest, MatchesCpuReferenceWithTexturesWrappingInU) {
    GlesBundleSpec spec;
    spec.wrapU = true;
    spec.seamInFront = true;
    for (const bool live : {false, true}) {
        for (const FrameCase& frame : {frameCases()[0], frameCases()[1]}) {
            FrameCase wrapped = frame;
            wrapped.name += live ? "_wrap_u_live" : "_wrap_u";
            wrapped.liveWeights = live;
            EXPECT_GE(comparePsnr(spec, wrapped), kWrapUDb)
                << wrapped.name << ": measured 58.68-62.42 dB (clamping instead: 43-52)";
            EXPECT_LE(largeDifferences_, kLargeDifferences) << wrapped.name;
        }
    }
    const FrameCase& frame = frameCases()[1];
    VirtualLight light;
    light.position = {frame.light[0], frame.light[1], frame.light[2]};
    const Vec3d viewer{frame.viewer[0], frame.viewer[1], frame.viewer[2]};
    const MappedTestBundle wrappedBundle(spec);
    spec.wrapU = false;
    const MappedTestBundle clampedBundle(spec);
    const BundleScene wrappedScene(wrappedBundle.view(), frame.preset);
    const BundleScene clampedScene(clampedBundle.view(), frame.preset);
    const ProjectorFrame wrapped = renderProjectorFrame(wrappedScene.scene(light, viewer));
    const ProjectorFrame clamped = renderProjectorFrame(clampedScene.scene(light, viewer));
    std::size_t differ = 0;
    for (std::size_t i = 0; i < wrapped.level.values.size(); ++i) {
        differ += std::fabs(wrapped.level.values[i] - clamped.level.values[i]) > 2.0f / 255 ? 1 : 0;
    }
    std::cout << differ
              << " channel values differ by more than 2 levels between wrapping and "
                 "clamping\n";
    EXPECT_GT(differ, 300u);  // measured 387
}

// The same frames with the regions' coded materials kept apart and blended by the preset's
// weights in projector space (live weights): two roundings of each code.
TEST_F(GlesFrameTest, LiveWeightsMatchCpuReference) {
    for (const FrameCase& frame : {frameCases()[0], frameCases()[3]}) {
        FrameCase live = frame;
        live.name += "_live";
        live.liveWeights = true;
        EXPECT_GE(comparePsnr({}, live), kLiveWeightsDb)
            << live.name << ": measured 58.37, 58.56 dB";
    }
}

// A relief (format 1.2) folded into the shading normal at load: the same frames as the CPU
// reference, which tilts its normals per pixel; one region has a relief and the other none, so
// the presets blend a relief with a flat region.
TEST_F(GlesFrameTest, ReliefMatchesCpuReference) {
    GlesBundleSpec spec;
    spec.relief = true;
    for (const FrameCase& frame : frameCases()) {
        FrameCase relief = frame;
        relief.name += "_relief";
        EXPECT_GE(comparePsnr(spec, relief), kReliefDb)
            << relief.name << ": measured 60.98-66.73 dB";
    }
}

// The relief follows the preset: folded again when the preset changes, and under live weights.
TEST_F(GlesFrameTest, ReliefFollowsPresetChangesAndLiveWeights) {
    GlesBundleSpec spec;
    spec.relief = true;
    FrameCase changed = frameCases()[1];  // radial
    changed.name += "_relief_after_stripes";
    changed.before = "stripes";
    EXPECT_GE(comparePsnr(spec, changed), kReliefDb) << "measured 62.17 dB, as without the change";
    for (const FrameCase& frame : {frameCases()[0], frameCases()[3]}) {
        FrameCase live = frame;
        live.name += "_relief_live";
        live.liveWeights = true;
        EXPECT_GE(comparePsnr(spec, live), kReliefLiveDb)
            << live.name << ": measured 60.35, 60.12 dB";
        live.name += "_after";
        live.before = frame.preset == "stripes" ? "radial" : "stripes";
        EXPECT_GE(comparePsnr(spec, live), kReliefLiveDb)
            << live.name << ": measured 60.35, 60.12 dB";
    }
}

// A relief on textures that tile in u, the seam turned to the projector: the relief pass
// samples the detail normals wrapping around, as the CPU reference does (its bumps do not tile,
// so clamping them instead shows at the seam).
TEST_F(GlesFrameTest, ReliefWrapsInUWithItsTextures) {
    GlesBundleSpec spec;
    spec.relief = true;
    spec.wrapU = true;
    spec.seamInFront = true;
    for (const bool live : {false, true}) {
        for (const FrameCase& frame : {frameCases()[0], frameCases()[1]}) {
            FrameCase wrapped = frame;
            wrapped.name += live ? "_relief_wrap_u_live" : "_relief_wrap_u";
            wrapped.liveWeights = live;
            EXPECT_GE(comparePsnr(spec, wrapped), kReliefWrapUDb)
                << wrapped.name
                << ": measured 58.77-62.62 dB (the relief clamped on the GPU instead: 50.1 dB, "
                   "15 pixels > 16 levels)";
            EXPECT_LE(largeDifferences_, kLargeDifferences) << wrapped.name;
        }
    }
}

// A preset change cross-fades: the first frame after it still shows the old preset, the last
// the new one, and in between every level lies between the two (f is linear in the material,
// the levels monotone in f). animating() tells the player to keep drawing meanwhile.
TEST_F(GlesFrameTest, PresetChangesCrossFade) {
    for (const bool live : {false, true}) {
        MappedTestBundle bundle;
        gles::GlesRendererOptions options;
        options.liveWeights = live;
        options.presetFadeSeconds = 0.5;
        gles::GlesFrameRenderer renderer(bundle.view(), options);
        std::unique_ptr<gles::RenderTarget> target =
            platform()->createRenderTarget(renderer.width(), renderer.height());
        gles::FrameInputs inputs;
        inputs.lightPosition = {0.4f, 0.3f, 0.5f};
        const auto frame = [&](double time) {
            inputs.timeSeconds = time;
            renderer.render(*target, inputs);
            target->present();
            return target->readRgba8();
        };
        renderer.selectPreset("stripes", false);
        const std::vector<std::uint8_t> stripes = frame(10.0);
        renderer.selectPreset("radial", false);
        const std::vector<std::uint8_t> radial = frame(10.0);
        renderer.selectPreset("stripes", false);
        EXPECT_EQ(frame(10.0), stripes);
        EXPECT_FALSE(renderer.animating());

        renderer.selectPreset("radial");
        EXPECT_TRUE(renderer.animating());
        EXPECT_EQ(frame(20.0), stripes) << "the fade starts from the old preset";
        const std::vector<std::uint8_t> middle = frame(20.25);
        EXPECT_TRUE(renderer.animating());
        std::size_t between = 0, outside = 0, changed = 0;
        for (std::size_t i = 0; i < middle.size(); ++i) {
            const int low = std::min(stripes[i], radial[i]), high = std::max(stripes[i], radial[i]);
            outside += (middle[i] + 1 < low || middle[i] > high + 1) ? 1 : 0;
            between += (high - low > 4 && middle[i] > low + 1 && middle[i] + 1 < high) ? 1 : 0;
            changed += high - low > 4 ? 1 : 0;
        }
        EXPECT_EQ(outside, 0u) << (live ? "live" : "static");
        EXPECT_GT(between, changed / 2) << (live ? "live" : "static");
        EXPECT_EQ(frame(20.5), radial) << (live ? "live" : "static");
        EXPECT_FALSE(renderer.animating());
    }
}

TEST_F(GlesFrameTest, UnknownPresetIsRefusedByName) {
    MappedTestBundle bundle;
    gles::GlesFrameRenderer renderer(bundle.view());
    EXPECT_EQ(renderer.presetName(), "stripes");
    try {
        renderer.selectPreset("gold");
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& error) {
        EXPECT_NE(
            std::string(error.what()).find("no weight preset 'gold' (it has: stripes, radial)"),
            std::string::npos)
            << error.what();
    }
}

// The failure evidence itself: a picture a person can open, with the frame's pixels.
TEST(FailureImageTest, WritesAPictureOfTheFrame) {
    std::vector<std::uint8_t> rgb(4 * 3 * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        rgb[i] = static_cast<std::uint8_t>(i * 7);
    }
    const std::string path = writeFailureImage("failure_image_test", 4, 3, rgb);
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path;
    std::ostringstream contents;
    contents << in.rdbuf();
    const std::string bytes = contents.str();
#if VPE_TEST_PNG
    EXPECT_EQ(path, "failure_image_test.png");
    ASSERT_GT(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
#else
    EXPECT_EQ(path, "failure_image_test.ppm");
    EXPECT_EQ(bytes.substr(0, 11), "P6\n4 3\n255\n");
    EXPECT_EQ(bytes.substr(11), std::string(rgb.begin(), rgb.end()));
#endif
    std::remove(path.c_str());
}

}  // namespace
}  // namespace vpe::renderer::testing
