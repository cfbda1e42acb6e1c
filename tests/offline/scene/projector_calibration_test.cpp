// SPDX-License-Identifier: MIT
// Projector calibration files (OpenCV YAML/XML/JSON, procam): round trips, key variants,
// refusals by key, the demo projector and distortion.
#include "vpe/scene/projector_calibration.h"

#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/screen_mesh.h"

#include "offline/scene/scene_test_support.h"
#include "offline/scene/tool_calibration_file.h"
#include "support/test_data.h"

namespace vpe::scene {
namespace {

using namespace test;  // NOLINT: the shared helpers of scene_test_support.h
using testing::TemporaryFolder;

ProjectorCalibration sampleCalibration() {
    ProjectorCalibration c = makeDemoProjector(0.8);
    c.distortion = {0.01, -0.002, 0.0003, -0.0004, 0.0005};
    c.K[1] = 0.25;  // a little skew
    return c;
}

void expectSameCalibration(const ProjectorCalibration& a, const ProjectorCalibration& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    for (std::size_t i = 0; i < 9; ++i) {
        EXPECT_NEAR(a.K[i], b.K[i], 1e-12 * std::max(1.0, std::fabs(a.K[i]))) << i;
        EXPECT_NEAR(a.R[i], b.R[i], 1e-15) << i;
    }
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_NEAR(a.distortion[i], b.distortion[i], 1e-16) << i;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.T[i], b.T[i], 1e-15) << i;
    }
}

TEST(ProjectorCalibration, RoundTripsThroughYamlXmlAndJson) {
    TemporaryFolder folder;
    const ProjectorCalibration written = sampleCalibration();
    for (const char* name : {"projector.yml", "projector.xml", "projector.json"}) {
        SCOPED_TRACE(name);
        writeProjectorCalibration(written, folder / name);
        expectSameCalibration(written, readProjectorCalibration(folder / name));
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 3);
    EXPECT_INPUT_ERROR(writeProjectorCalibration(written, folder / "projector.txt"),
                       "unsupported calibration format '.txt'");
}

// What procam-calibration's Application::calibrate writes (numbers from a made-up rig): no
// resolution, T in millimetres.
constexpr const char* kProcamYaml = R"(%YAML:1.0
cam_K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 2.3e+03, 0., 1.2e+03, 0., 2.3e+03, 9.0e+02, 0., 0., 1. ]
cam_kc: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0.1, -0.2, 0., 0., 0. ]
proj_K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 1.8e+03, 0., 5.1e+02, 0., 1.8e+03, 7.5e+02, 0., 0., 1. ]
proj_kc: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -0.05, 0.1, 0.001, 0.002, 0. ]
R: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 0.9950041652780258, 0., 0.09983341664682815, 0., 1., 0., -0.09983341664682815, 0., 0.9950041652780258 ]
T: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ -150., 10., 20. ]
b: 0.3
m: 5
stereo_error: 0.42
)";

TEST(ProjectorCalibration, ReadsProcamCalibrationFilesWithTheirUnitAndResolution) {
    TemporaryFolder folder;
    writeFile(folder / "calibration.yml", kProcamYaml);
    ProjectorCalibrationOverrides overrides;
    overrides.width = 1024;
    overrides.height = 768;
    overrides.metresPerUnit = 0.001;
    const ProjectorCalibration c = readProjectorCalibration(folder / "calibration.yml", overrides);
    EXPECT_EQ(c.width, 1024);
    EXPECT_EQ(c.height, 768);
    EXPECT_DOUBLE_EQ(c.K[0], 1800);
    EXPECT_DOUBLE_EQ(c.K[2], 510);
    EXPECT_DOUBLE_EQ(c.K[5], 750);
    EXPECT_DOUBLE_EQ(c.distortion[0], -0.05);
    EXPECT_DOUBLE_EQ(c.distortion[3], 0.002);
    EXPECT_DOUBLE_EQ(c.T[0], -0.15);
    EXPECT_DOUBLE_EQ(c.R[2], 0.09983341664682815);

    // Without a resolution the file is incomplete; without a unit, 150 "m" is implausible.
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "calibration.yml"),
                       "calibration.yml: no projector resolution (keys proj_width/proj_height "
                       "or image_width/image_height): give it on the command line");
    overrides.metresPerUnit.reset();
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "calibration.yml", overrides),
                       "calibration.yml: T: the projector would be");
}

// A vpe-style YAML calibration with one line replaced.
std::string yamlWith(const std::string& key, const std::string& value) {
    std::map<std::string, std::string> entries{
        {"proj_width", "1920"},
        {"proj_height", "1080"},
        {"proj_K",
         "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 2000., 0., "
         "959.5, 0., 2000., 539.5, 0., 0., 1. ]"},
        {"proj_kc",
         "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., "
         "0., 0. ]"},
        {"R",
         "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., "
         "-1., 0., 0., 0., -1. ]"},
        {"T", "!!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0., 0.075, 0.8 ]"},
        {"length_unit", "\"m\""},
    };
    if (value.empty()) {
        entries.erase(key);
    } else {
        entries[key] = value;
    }
    std::string text = "%YAML:1.0\n---\n";
    for (const auto& [k, v] : entries) {
        text += k + ": " + v + "\n";
    }
    return text;
}

std::string matrix(int rows, int cols, const std::string& data) {
    return "!!opencv-matrix\n   rows: " + std::to_string(rows) +
           "\n   cols: " + std::to_string(cols) + "\n   dt: d\n   data: [ " + data + " ]";
}

TEST(ProjectorCalibration, ReadsTheBaseFixture) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("", ""));
    const ProjectorCalibration c = readProjectorCalibration(folder / "p.yml");
    EXPECT_EQ(c.width, 1920);
    const proto::Vec3d centre = c.center();
    EXPECT_NEAR(centre.z, 0.8, 1e-15);
    EXPECT_NEAR(centre.y, 0.075, 1e-15);
}

TEST(ProjectorCalibration, ReadsARodriguesRotationAndImageSizeKeys) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("R", matrix(3, 1, "3.141592653589793, 0., 0.")));
    const ProjectorCalibration c = readProjectorCalibration(folder / "p.yml");
    const std::array<double, 9> flipped{1, 0, 0, 0, -1, 0, 0, 0, -1};
    for (std::size_t i = 0; i < 9; ++i) {
        EXPECT_NEAR(c.R[i], flipped[i], 1e-12);
    }
    std::string other = yamlWith("proj_width", "");
    other = other.substr(0, other.find("proj_height")) +
            other.substr(other.find('\n', other.find("proj_height")) + 1);
    writeFile(folder / "q.yml", other + "image_width: 800\nimage_height: 600\n");
    const ProjectorCalibration q = readProjectorCalibration(folder / "q.yml");
    EXPECT_EQ(q.width, 800);
    EXPECT_EQ(q.height, 600);
}

TEST(ProjectorCalibration, RefusesEachBadKeyByName) {
    TemporaryFolder folder;
    const auto refuse = [&](const std::string& key, const std::string& value,
                            const std::string& fragment) {
        SCOPED_TRACE(key + " = " + value);
        writeFile(folder / "p.yml", yamlWith(key, value));
        EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.yml"), "p.yml: " + fragment);
    };
    refuse("proj_K", "", "proj_K: missing");
    refuse("R", "", "R: missing");
    refuse("T", "", "T: missing");
    refuse("proj_K", matrix(3, 3, "-2000., 0., 959.5, 0., 2000., 539.5, 0., 0., 1."),
           "proj_K: focal lengths must be positive (fx = -2000, fy = 2000)");
    refuse("proj_K", matrix(3, 3, "2000., 0., 959.5, 0., 0., 539.5, 0., 0., 1."),
           "proj_K: focal lengths must be positive");
    refuse("proj_K", matrix(3, 3, "2000., 0., 959.5, 0., 2000., 539.5, 0., 0., 2."),
           "proj_K: not an intrinsic matrix");
    refuse("proj_K", matrix(2, 3, "2000., 0., 959.5, 0., 2000., 539.5"),
           "proj_K: expected a 3x3 matrix, found 2x3");
    refuse("proj_K", matrix(3, 3, "2000., 0., .nan, 0., 2000., 539.5, 0., 0., 1."),
           "proj_K: element 2 is not a finite number");
    refuse("proj_K", "banana", "proj_K: not a matrix of numbers");
    refuse("proj_kc", matrix(1, 8, "0., 0., 0., 0., 0., 0.1, 0., 0."),
           "proj_kc: coefficient 6 is not zero");
    refuse("proj_kc", matrix(1, 3, "0., 0., 0."), "proj_kc: expected 4 or 5 distortion");
    refuse("R", matrix(3, 3, "1., 0., 0., 0., 1., 0.01, 0., 0., 1."),
           "R: not orthonormal (RᵀR differs from I by");
    refuse("R", matrix(3, 3, "1., 0., 0., 0., 1., 0., 0., 0., -1."),
           "R: determinant -1, not +1 (a reflection, not a rotation)");
    refuse("T", matrix(3, 1, "0., .inf, 0.8"), "T: element 1 is not a finite number");
    refuse("T", matrix(2, 1, "0., 0.8"), "T: expected a 3-vector, found 2x1");
    refuse("proj_width", "0", "projector resolution 0x1080 is outside 1..8192");
    refuse("proj_height", "9000", "projector resolution 1920x9000 is outside 1..8192");
    refuse("proj_width", "19.5", "proj_width: expected a whole number of pixels");
    refuse("proj_height", "", "proj_height: missing (given proj_width without it)");
    refuse("length_unit", "\"furlong\"", "length_unit: 'furlong' is not m, cm or mm");
}

TEST(ProjectorCalibration, RefusesConflictingResolution) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("", ""));
    ProjectorCalibrationOverrides overrides;
    overrides.width = 1280;
    overrides.height = 720;
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.yml", overrides),
                       "p.yml: proj_width: the file says 1920x1080 but 1280x720 was given");
    overrides.width = 1920;
    overrides.height = 1080;
    EXPECT_EQ(readProjectorCalibration(folder / "p.yml", overrides).width, 1920);
}

TEST(ProjectorCalibration, RefusesMissingAndUnparsableFiles) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "absent.yml"),
                       "absent.yml: cannot open projector calibration: no such file");
    writeFile(folder / "junk.yml", "%YAML:1.0\nproj_K: [ 1, 2\n  : : ]]\n");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "junk.yml"),
                       "junk.yml:3: cannot parse projector calibration: Missing , between the "
                       "elements");
    writeFile(folder / "junk.xml", "<?xml version=\"1.0\"?>\n<opencv_storage><proj_K>");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "junk.xml"),
                       "junk.xml:2: cannot parse projector calibration: ");
    writeFile(folder / "words.json", "not json at all");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "words.json"),
                       "words.json: cannot parse projector calibration: ");
    // Without the %YAML line the line numbers are still the file's.
    writeFile(folder / "bare.yml", "proj_width: 10\nproj_K: [ 1, 2\n  : : ]]\n");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "bare.yml"),
                       "bare.yml:3: cannot parse projector calibration: ");
}

TEST(ProjectorCalibration, ReadsYamlWithoutItsDirectiveLine) {
    TemporaryFolder folder;
    std::string text = yamlWith("", "");
    text = text.substr(text.find("---\n") + 4);
    writeFile(folder / "bare.yaml", text);
    EXPECT_EQ(readProjectorCalibration(folder / "bare.yaml").height, 1080);
    // Plain lists of numbers are accepted for matrices.
    writeFile(folder / "lists.yml",
              "proj_width: 640\nproj_height: 480\nproj_K: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]\n"
              "R: [0, 0, 0]\nT: [0, 0, 1]\n");
    const ProjectorCalibration c = readProjectorCalibration(folder / "lists.yml");
    EXPECT_EQ(c.K[0], 500);
    EXPECT_EQ(c.R[0], 1);
    EXPECT_EQ(c.T[2], 1);
}

// The camera of a procam rig, at the origin of its own frame (the object frame of a procam
// file), with a little distortion.
proto::PinholeCamera sampleCamera() {
    proto::PinholeCamera camera;
    camera.width = 1640;
    camera.height = 1232;
    camera.K = {1250, 0.125, 819.5, 0, 1252, 615.5, 0, 0, 1};
    camera.distortion = {-0.12, 0.08, 0.0004, -0.0003, -0.01};
    return camera;
}

TEST(CameraCalibration, RoundTripsBesideTheProjectorInYamlXmlAndJson) {
    TemporaryFolder folder;
    const ProjectorCalibration projector = sampleCalibration();
    const proto::PinholeCamera camera = sampleCamera();
    for (const char* name : {"procam.yml", "procam.xml", "procam.json"}) {
        SCOPED_TRACE(name);
        writeProcamCalibration(projector, camera, 0.42, folder / name);
        expectSameCalibration(projector, readProjectorCalibration(folder / name));
        const std::optional<proto::PinholeCamera> read = readCameraCalibration(folder / name);
        ASSERT_TRUE(read.has_value());
        expectSameCalibration(camera, *read);
    }
    // A file without the camera's keys has no camera: every projector-only file.
    writeProjectorCalibration(projector, folder / "projector.yml");
    EXPECT_FALSE(readCameraCalibration(folder / "projector.yml").has_value());
    writeProcamCalibration(projector, std::nullopt, std::nullopt, folder / "alone.yml");
    EXPECT_FALSE(readCameraCalibration(folder / "alone.yml").has_value());
    expectSameCalibration(projector, readProjectorCalibration(folder / "alone.yml"));
}

TEST(CameraCalibration, ReadsProcamsCameraAtTheOriginOnceItsResolutionIsGiven) {
    TemporaryFolder folder;
    // procam-calibration writes cam_K and cam_kc but not the camera's resolution.
    writeFile(folder / "calibration.yml", kProcamYaml);
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "calibration.yml"),
                       "calibration.yml: cam_width: missing (cam_K needs the camera's "
                       "resolution: cam_width and cam_height, pixels)");
    writeFile(folder / "calibration.yml", std::string(kProcamYaml) + "cam_width: 2400\n");
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "calibration.yml"),
                       "calibration.yml: cam_height: missing (given cam_width without it)");
    writeFile(folder / "calibration.yml",
              std::string(kProcamYaml) + "cam_width: 2400\ncam_height: 1800\n");
    const std::optional<proto::PinholeCamera> camera =
        readCameraCalibration(folder / "calibration.yml");
    ASSERT_TRUE(camera.has_value());
    EXPECT_EQ(camera->width, 2400);
    EXPECT_EQ(camera->height, 1800);
    EXPECT_DOUBLE_EQ(camera->K[0], 2300);
    EXPECT_DOUBLE_EQ(camera->K[5], 900);
    EXPECT_DOUBLE_EQ(camera->distortion[1], -0.2);
    // The file's R, T are the projector's (camera → projector): the camera is the origin.
    EXPECT_EQ(camera->R, (std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
    EXPECT_EQ(camera->T, (std::array<double, 3>{0, 0, 0}));
}

TEST(CameraCalibration, RefusesEachBadCameraKeyByName) {
    TemporaryFolder folder;
    const auto refuse = [&](const std::string& extra, const std::string& fragment) {
        SCOPED_TRACE(extra);
        writeFile(folder / "p.yml", yamlWith("", "") + extra);
        EXPECT_INPUT_ERROR(readCameraCalibration(folder / "p.yml"), "p.yml: " + fragment);
    };
    refuse("cam_width: 640\ncam_height: 480\ncam_K: " +
               matrix(3, 3, "-500., 0., 319.5, 0., 500., 239.5, 0., 0., 1.") + "\n",
           "cam_K: focal lengths must be positive (fx = -500, fy = 500)");
    refuse(
        "cam_width: 640\ncam_height: 480\ncam_K: " + matrix(2, 3, "1., 2., 3., 4., 5., 6.") + "\n",
        "cam_K: expected a 3x3 matrix, found 2x3");
    refuse("cam_width: 640\ncam_height: 480\ncam_K: " +
               matrix(3, 3, "500., 0., 319.5, 0., 500., 239.5, 0., 0., 1.") +
               "\ncam_kc: " + matrix(1, 3, "0., 0., 0.") + "\n",
           "cam_kc: expected 4 or 5 distortion coefficients");
    refuse("cam_width: 0\ncam_height: 480\ncam_K: " +
               matrix(3, 3, "500., 0., 319.5, 0., 500., 239.5, 0., 0., 1.") + "\n",
           "camera resolution 0x480 is outside 1..8192");
    refuse("cam_width: 640.5\ncam_height: 480\ncam_K: " +
               matrix(3, 3, "500., 0., 319.5, 0., 500., 239.5, 0., 0., 1.") + "\n",
           "cam_width: expected a whole number of pixels");
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "absent.yml"),
                       "absent.yml: cannot open camera calibration: no such file");
}

TEST(CameraCalibration, WritesOnlyACameraAtTheOriginIntoAProcamFile) {
    TemporaryFolder folder;
    proto::PinholeCamera moved = sampleCamera();
    moved.T = {0, 0, 0.5};
    EXPECT_INPUT_ERROR(
        writeProcamCalibration(sampleCalibration(), moved, std::nullopt, folder / "p.yml"),
        "p.yml: cam_K: the camera's pose must be R = I, T = 0 (a procam file's object frame is "
        "the camera's)");
    proto::PinholeCamera flat = sampleCamera();
    flat.K[4] = 0;
    EXPECT_INPUT_ERROR(
        writeProcamCalibration(sampleCalibration(), flat, std::nullopt, folder / "p.yml"),
        "p.yml: cam_K: focal lengths must be positive");
    EXPECT_INPUT_ERROR(
        writeProcamCalibration(sampleCalibration(), sampleCamera(), -1.0, folder / "p.yml"),
        "p.yml: stereo_error: -1 is not a finite value ≥ 0");
    EXPECT_FALSE(std::filesystem::exists(folder / "p.yml"));
}

TEST(CameraCalibration, ACameraFileCarriesItsOwnPose) {
    TemporaryFolder folder;
    proto::PinholeCamera camera = sampleCamera();
    camera.R = {1, 0, 0, 0, 0, -1, 0, 1, 0};  // looking down: +z of the camera is −y
    camera.T = {0.02, -0.1, 2.4};
    writeCameraCalibration(camera, folder / "camera.yml");
    const std::optional<proto::PinholeCamera> read =
        readCameraCalibration(folder / "camera.yml", CameraPose::kFromFile);
    ASSERT_TRUE(read.has_value());
    expectSameCalibration(camera, *read);
    // Read as a procam file it sits at the origin instead.
    EXPECT_EQ(readCameraCalibration(folder / "camera.yml")->T, (std::array<double, 3>{0, 0, 0}));
    // A pose in millimetres without its unit is refused as procam's are.
    writeFile(folder / "mm.yml",
              "cam_width: 640\ncam_height: 480\ncam_K: [500, 0, 319.5, 0, "
              "500, 239.5, 0, 0, 1]\nR: [0, 0, 0]\nT: [0, 0, 2400]\n");
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "mm.yml", CameraPose::kFromFile),
                       "mm.yml: T: the camera would be 2400 m from the origin");
    writeFile(folder / "none.yml",
              "cam_width: 640\ncam_height: 480\ncam_K: [500, 0, 319.5, 0, "
              "500, 239.5, 0, 0, 1]\n");
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "none.yml", CameraPose::kFromFile),
                       "none.yml: R: missing (the camera's pose needs R and T)");
}

// kamino410/procam-calibration's calibration_result.xml holding a vpe rig: the projector (in
// the camera's frame, with its distortion and skew) and the camera, T in millimetres.
TEST(ToolCalibration, ReadsCalibrationResultAsTheSameRig) {
    TemporaryFolder folder;
    const ProjectorCalibration projector = sampleCalibration();
    const proto::PinholeCamera camera = sampleCamera();
    writeFile(folder / "calibration_result.xml",
              testing::toolCalibrationXml(projector, camera, 0.42));
    ProjectorCalibrationOverrides overrides;
    overrides.defaultWidth = 1920;  // a scan's projector: the file has no size
    overrides.defaultHeight = 1080;
    overrides.metresPerUnit = 0.001;
    const ProjectorCalibration read =
        readProjectorCalibration(folder / "calibration_result.xml", overrides);
    const auto expectSameRig = [](const proto::PinholeCamera& a, const proto::PinholeCamera& b) {
        EXPECT_EQ(a.width, b.width);
        EXPECT_EQ(a.height, b.height);
        EXPECT_EQ(a.K, b.K);
        EXPECT_EQ(a.distortion, b.distortion);
        EXPECT_EQ(a.R, b.R);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_NEAR(a.T[i], b.T[i], 1e-15) << i;  // through millimetres
        }
    };
    expectSameRig(projector, read);
    const std::optional<proto::PinholeCamera> readCamera =
        readCameraCalibration(folder / "calibration_result.xml");
    ASSERT_TRUE(readCamera.has_value());
    expectSameRig(camera, *readCamera);  // 1640 x 1232 from img_shape (rows, cols)

    // The direction, as the tool defines it ("rotation matrix / translation vector from camera
    // to projector: they translate points from camera coord to projector coord"): a point of
    // the camera's frame, taken to the projector's by the file's numbers by hand, lands on the
    // pixel vpe projects it to; and the projector's centre is −Rᵀ·T.
    ProjectorCalibration pinhole = projector;
    pinhole.distortion = {};
    pinhole.K[1] = 0;
    writeFile(folder / "pinhole.xml", testing::toolCalibrationXml(pinhole, camera, 0.42));
    const ProjectorCalibration straight =
        readProjectorCalibration(folder / "pinhole.xml", overrides);
    const std::array<double, 9>& R = pinhole.R;
    const std::array<double, 3> t{pinhole.T[0] * 1000, pinhole.T[1] * 1000, pinhole.T[2] * 1000};
    for (const proto::Vec3d& X : {proto::Vec3d{0, 0.075, 0}, proto::Vec3d{0.05, 0.12, -0.03}}) {
        const double mm[3] = {1000 * X.x, 1000 * X.y, 1000 * X.z};
        double x[3];
        for (int r = 0; r < 3; ++r) {
            x[r] = R[3 * r] * mm[0] + R[3 * r + 1] * mm[1] + R[3 * r + 2] * mm[2] + t[r];
        }
        const auto pixel = proto::projectToPixel(straight, X);
        ASSERT_TRUE(pixel);
        EXPECT_NEAR(pixel->x, pinhole.K[0] * x[0] / x[2] + pinhole.K[2], 1e-9);
        EXPECT_NEAR(pixel->y, pinhole.K[4] * x[1] / x[2] + pinhole.K[5], 1e-9);
    }
    const proto::Vec3d centre = straight.center();
    EXPECT_NEAR(centre.x, -(R[0] * t[0] + R[3] * t[1] + R[6] * t[2]) / 1000, 1e-15);
    EXPECT_NEAR(centre.y, -(R[1] * t[0] + R[4] * t[1] + R[7] * t[2]) / 1000, 1e-15);
    EXPECT_NEAR(centre.z, -(R[2] * t[0] + R[5] * t[1] + R[8] * t[2]) / 1000, 1e-15);

    // The tool's first versions spelt the rotation "roration".
    writeFile(folder / "old.xml",
              testing::toolCalibrationXml(projector, camera, 0.42, 0.001, "roration"));
    expectSameRig(projector, readProjectorCalibration(folder / "old.xml", overrides));
    // A projector size in the file wins over the scan's default (which the scan then checks).
    writeFile(folder / "sized.xml",
              testing::toolCalibrationXml(projector, camera, 0.42)
                  .insert(std::string("<?xml version=\"1.0\"?>\n<opencv_storage>\n").size(),
                          "<proj_width>1280</proj_width><proj_height>720</proj_height>\n"));
    EXPECT_EQ(readProjectorCalibration(folder / "sized.xml", overrides).width, 1280);
}

TEST(ToolCalibration, RefusesWhatItCannotReadByKey) {
    TemporaryFolder folder;
    const std::string good = testing::toolCalibrationXml(sampleCalibration(), sampleCamera(), 0.42);
    const auto withLine = [&](const std::string& line) {
        return std::string(good).insert(good.find("<rms>"), line + "\n");
    };
    ProjectorCalibrationOverrides overrides;
    overrides.width = 1920;
    overrides.height = 1080;
    // No unit: 0.80 m read as 803.5 m.
    writeFile(folder / "p.xml", good);
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: translation: the projector would be 803.5");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "give the unit (length_unit in the file, or the command's "
                       "--calibration-unit)");
    // No size from the file or the command line.
    overrides.metresPerUnit = 0.001;
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", {}),
                       "p.xml: no projector resolution");
    // A unit in the file that the command line contradicts.
    writeFile(folder / "p.xml", withLine("<length_unit>m</length_unit>"));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: length_unit: the file says m but 0.001 m per unit was given");
    // Keys of neither layout, named; keys of both; both spellings of the rotation.
    writeFile(folder / "p.xml", withLine("<held_out_rms>1.2</held_out_rms>"));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: unknown key held_out_rms: neither vpe's calibration keys");
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "p.xml"), "p.xml: unknown key held_out_rms");
    writeFile(folder / "p.xml", withLine("<cam_shape>1</cam_shape><proj_shape>2</proj_shape>"));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: unknown keys cam_shape, proj_shape: neither");
    writeFile(folder / "p.xml", withLine("<T>0 0 1</T>"));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: mixes vpe's keys (T) with procam-calibration's calibration_result "
                       "keys (");
    writeFile(folder / "p.xml",
              withLine(testing::toolMatrix("roration", 3, 3, sampleCalibration().R)));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: roration: given beside rotation");
    // The tool's own keys checked under their names.
    ProjectorCalibration flat = sampleCalibration();
    flat.K[0] = -5;
    writeFile(folder / "p.xml", testing::toolCalibrationXml(flat, sampleCamera(), 0.42));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: proj_int: focal lengths must be positive (fx = -5");
    ProjectorCalibration mirrored = sampleCalibration();
    for (std::size_t i = 6; i < 9; ++i) {
        mirrored.R[i] = -mirrored.R[i];
    }
    writeFile(folder / "p.xml", testing::toolCalibrationXml(mirrored, sampleCamera(), 0.42));
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: rotation: determinant -1");
    std::string noTranslation = good;
    noTranslation.erase(
        noTranslation.find("<translation"),
        noTranslation.find("</opencv_storage>") - noTranslation.find("<translation"));
    writeFile(folder / "p.xml", noTranslation);
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.xml", overrides),
                       "p.xml: translation: missing (a projector calibration needs proj_int, "
                       "rotation and translation)");
    // The camera: its size from img_shape, which cam_width/cam_height must not contradict; and
    // the file's pose is the projector's, never a camera's.
    writeFile(folder / "p.xml", withLine("<cam_width>640</cam_width><cam_height>480</cam_height>"));
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "p.xml"),
                       "p.xml: cam_width: the file says 640x480 but img_shape says 1640x1232");
    std::string shapeless = good;
    shapeless.erase(0, shapeless.find("<rms>"));
    shapeless.insert(0, "<?xml version=\"1.0\"?>\n<opencv_storage>\n");
    writeFile(folder / "p.xml", shapeless);
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "p.xml"), "p.xml: img_shape: missing");
    writeFile(folder / "p.xml", good);
    EXPECT_INPUT_ERROR(readCameraCalibration(folder / "p.xml", CameraPose::kFromFile),
                       "p.xml: rotation: procam-calibration's rotation and translation are the "
                       "projector's pose");
}

// vpe's own files: a key vpe does not know is refused too, naming it.
TEST(ProjectorCalibration, RefusesAnUnknownKeyNamingIt) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("", "") + "proj_skew: 0.1\n");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.yml"),
                       "p.yml: unknown key proj_skew: neither vpe's calibration keys");
    writeFile(folder / "p.yml", yamlWith("", "") + "cam_error: 0.2\nproj_error: 0.1\nE: 1\nF: 2\n");
    EXPECT_EQ(readProjectorCalibration(folder / "p.yml").width, 1920);
}

TEST(ProjectorCalibration, DemoProjectorFramesTheVase) {
    const ProjectorCalibration c = makeDemoProjector(0.8);
    EXPECT_EQ(c.width, 1920);
    EXPECT_EQ(c.height, 1080);
    // 30° vertical field of view.
    EXPECT_NEAR(2 * std::atan(0.5 * c.height / c.K[4]) * 180 / M_PI, 30.0, 1e-9);
    const proto::Vec3d centre = c.center();
    EXPECT_NEAR(centre.x, 0, 1e-15);
    EXPECT_NEAR(centre.y, 0.075, 1e-15);
    EXPECT_NEAR(centre.z, 0.8, 1e-15);
    const auto middle = projectToPixel(c, {0, 0.075, 0});
    ASSERT_TRUE(middle);
    EXPECT_NEAR(middle->x, 959.5, 1e-9);
    EXPECT_NEAR(middle->y, 539.5, 1e-9);
    // The lip is above the middle on the image (rows grow downwards); right is right.
    EXPECT_LT(projectToPixel(c, {0, 0.15, 0.04})->y, 539.5);
    EXPECT_GT(projectToPixel(c, {0.05, 0.075, 0})->x, 959.5);
    const ScreenMesh vase = makeProceduralVase();
    for (const Vec3f& p : vase.positions) {
        const auto pixel = projectToPixel(
            c, {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)});
        ASSERT_TRUE(pixel);
        EXPECT_GT(pixel->x, 0);
        EXPECT_LT(pixel->x, c.width - 1);
        EXPECT_GT(pixel->y, 0);
        EXPECT_LT(pixel->y, c.height - 1);
    }
    EXPECT_FALSE(projectToPixel(c, {0, 0.075, 2.0}));  // behind the projector
}

TEST(ProjectorCalibration, ProjectionAppliesOpenCvDistortion) {
    ProjectorCalibration c = makeDemoProjector(1.0, {0, 0, 0});
    c.distortion = {0.1, 0, 0, 0, 0};
    // Point at normalized (0.1, 0) (x right in the image is +x in the world here):
    // r² = 0.01, radial 1.001.
    const auto pixel = projectToPixel(c, {0.1, 0, 0});
    ASSERT_TRUE(pixel);
    EXPECT_NEAR(pixel->x, c.K[2] + c.K[0] * 0.1 * 1.001, 1e-9);
}

}  // namespace
}  // namespace vpe::scene
