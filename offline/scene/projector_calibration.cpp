// SPDX-License-Identifier: MIT
// Projector calibration files through OpenCV's FileStorage.
//
// Key names: Moreno & Taubin's procam-calibration (Brown University, 2012;
// Application::calibrate in src/Application.cpp) writes calibration.yml with
//   fs << "cam_K" << cam_K << "cam_kc" << cam_kc << "proj_K" << proj_K << "proj_kc" << proj_kc
//      << "R" << R << "T" << T << "b" << ... << "m" << ... << "stereo_error" << ...;
// where R, T come from cv::stereoCalibrate(camera, projector): camera → projector
// coordinates, T in the chessboard's unit; proj_kc has OpenCV's five coefficients (k3 fixed
// at 0 by CALIB_FIX_K3). It does not write the projector's resolution.
#include "vpe/scene/projector_calibration.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "vpe/common/atomic_output.h"
#include "vpe/common/input_error.h"
#include "vpe/text/line_reader.h"

namespace vpe::scene {

namespace {

constexpr int kMaxResolution = 8192;
constexpr double kRotationTolerance = 1e-3;
constexpr double kMaxUnitlessDistance = 20.0;  // metres; beyond, T is probably in mm

std::string formatNumber(double value) {
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

std::string oneLine(std::string text) {
    std::replace_if(
        text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    return text;
}

// A matrix-valued key: its numbers in row-major order and its shape. OpenCV matrices
// (!!opencv-matrix / opencv-matrix type_id) and plain sequences of numbers are accepted.
struct Numbers {
    std::vector<double> values;
    int rows = 0, cols = 0;
};

class CalibrationReader {
public:
    CalibrationReader(const std::filesystem::path& path, cv::FileStorage& storage)
        : path_(path), storage_(storage) {}

    bool has(const char* key) const {
        const cv::FileNode node = storage_[key];
        return !node.empty() && !node.isNone();
    }

    std::optional<Numbers> numbers(const char* key) const {
        const cv::FileNode node = storage_[key];
        if (node.empty() || node.isNone()) {
            return std::nullopt;
        }
        Numbers out;
        try {
            if (node.isSeq()) {
                for (const cv::FileNode& item : node) {
                    if (!item.isInt() && !item.isReal()) {
                        throw InputError(path_, std::string(key) + ": not a list of numbers");
                    }
                    out.values.push_back(static_cast<double>(item));
                }
                out.rows = 1;
                out.cols = static_cast<int>(out.values.size());
            } else {
                cv::Mat matrix;
                node >> matrix;
                if (matrix.empty() || matrix.channels() != 1) {
                    throw InputError(path_, std::string(key) + ": not a matrix of numbers");
                }
                matrix.convertTo(matrix, CV_64F);
                out.rows = matrix.rows;
                out.cols = matrix.cols;
                for (int r = 0; r < matrix.rows; ++r) {
                    for (int c = 0; c < matrix.cols; ++c) {
                        out.values.push_back(matrix.at<double>(r, c));
                    }
                }
            }
        } catch (const cv::Exception& error) {
            throw InputError(
                path_, std::string(key) + ": not a matrix of numbers (" + oneLine(error.err) + ")");
        }
        for (std::size_t i = 0; i < out.values.size(); ++i) {
            if (!std::isfinite(out.values[i])) {
                throw InputError(path_, std::string(key) + ": element " + std::to_string(i) +
                                            " is not a finite number");
            }
        }
        return out;
    }

    Numbers required(const char* key) const {
        auto value = numbers(key);
        if (!value) {
            throw InputError(path_, std::string(key) +
                                        ": missing (a projector calibration "
                                        "needs proj_K, R and T)");
        }
        return *value;
    }

    std::optional<int> integer(const char* key) const {
        const cv::FileNode node = storage_[key];
        if (node.empty() || node.isNone()) {
            return std::nullopt;
        }
        if (node.isInt()) {
            return static_cast<int>(node);
        }
        if (node.isReal()) {
            const double value = static_cast<double>(node);
            if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 1e9) {
                return static_cast<int>(value);
            }
        }
        throw InputError(path_, std::string(key) + ": expected a whole number of pixels");
    }

    std::optional<std::string> string(const char* key) const {
        const cv::FileNode node = storage_[key];
        if (node.empty() || node.isNone()) {
            return std::nullopt;
        }
        if (!node.isString()) {
            throw InputError(path_, std::string(key) + ": expected a string");
        }
        return static_cast<std::string>(node);
    }

private:
    const std::filesystem::path& path_;
    cv::FileStorage& storage_;
};

std::string shape(const Numbers& n) {
    return std::to_string(n.rows) + "x" + std::to_string(n.cols);
}

// R from a Rodrigues rotation vector (axis × angle in radians).
std::array<double, 9> rotationFromVector(const std::vector<double>& r) {
    const double angle = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (angle < 1e-15) {
        return {1, 0, 0, 0, 1, 0, 0, 0, 1};
    }
    const double x = r[0] / angle, y = r[1] / angle, z = r[2] / angle;
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
            t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
            t * x * z - s * y, t * y * z + s * x, t * z * z + c};
}

std::optional<double> metresPerUnitOf(const std::string& unit) {
    if (unit == "m") {
        return 1.0;
    }
    if (unit == "cm") {
        return 0.01;
    }
    if (unit == "mm") {
        return 0.001;
    }
    return std::nullopt;
}

std::string lowercaseExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

// OpenCV 4's parsers report "(-212) <parser function> in function 'NAME(LINE): problem'":
// the useful part is in Exception::func for parse errors, in Exception::err otherwise.
InputError parseError(const std::filesystem::path& path, const cv::Exception& failure,
                      int addedLines) {
    if (failure.code == cv::Error::StsParseError) {
        const std::string& where = failure.func;
        const std::size_t open = where.rfind('(', where.find("): "));
        const std::size_t close = where.find("): ");
        if (open != std::string::npos && close != std::string::npos && close > open) {
            int line = 0;
            const auto [end, error] =
                std::from_chars(where.data() + open + 1, where.data() + close, line);
            if (error == std::errc() && end == where.data() + close) {
                return InputError(
                    path, std::max(1, line - addedLines),
                    "cannot parse projector calibration: " + oneLine(where.substr(close + 3)));
            }
        }
        return InputError(path, "cannot parse projector calibration: " + oneLine(where));
    }
    return InputError(path, "cannot parse projector calibration: " + oneLine(failure.err));
}

}  // namespace

void validateProjectorCalibration(const ProjectorCalibration& c,
                                  const std::filesystem::path& source) {
    if (c.width < 1 || c.width > kMaxResolution || c.height < 1 || c.height > kMaxResolution) {
        throw InputError(source, "projector resolution " + std::to_string(c.width) + "x" +
                                     std::to_string(c.height) + " is outside 1..8192");
    }
    const auto allFinite = [](const auto& values) {
        return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    };
    if (!allFinite(c.K)) {
        throw InputError(source, "proj_K: not all finite numbers");
    }
    if (!allFinite(c.distortion)) {
        throw InputError(source, "proj_kc: not all finite numbers");
    }
    if (!allFinite(c.R)) {
        throw InputError(source, "R: not all finite numbers");
    }
    if (!allFinite(c.T)) {
        throw InputError(source, "T: not all finite numbers");
    }
    if (!(c.K[0] > 0) || !(c.K[4] > 0)) {
        throw InputError(source, "proj_K: focal lengths must be positive (fx = " +
                                     formatNumber(c.K[0]) + ", fy = " + formatNumber(c.K[4]) + ")");
    }
    if (c.K[3] != 0 || c.K[6] != 0 || c.K[7] != 0 || std::fabs(c.K[8] - 1) > 1e-9) {
        throw InputError(source,
                         "proj_K: not an intrinsic matrix (expected [fx s cx; 0 fy cy; "
                         "0 0 1])");
    }
    const auto& r = c.R;
    double worst = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double dot =
                r[static_cast<std::size_t>(i)] * r[static_cast<std::size_t>(j)] +
                r[static_cast<std::size_t>(3 + i)] * r[static_cast<std::size_t>(3 + j)] +
                r[static_cast<std::size_t>(6 + i)] * r[static_cast<std::size_t>(6 + j)];
            worst = std::max(worst, std::fabs(dot - (i == j ? 1.0 : 0.0)));
        }
    }
    if (worst > kRotationTolerance) {
        throw InputError(source, "R: not orthonormal (RᵀR differs from I by " +
                                     formatNumber(worst) + ", tolerance 1e-3)");
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (std::fabs(det - 1) > kRotationTolerance) {
        throw InputError(source, "R: determinant " + formatNumber(det) +
                                     ", not +1 (a reflection, not a rotation)");
    }
}

ProjectorCalibration readProjectorCalibration(const std::filesystem::path& path,
                                              const ProjectorCalibrationOverrides& overrides) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        throw InputError(path, std::filesystem::exists(path, error)
                                   ? "cannot open projector calibration: not a regular file"
                                   : "cannot open projector calibration: no such file");
    }
    // Read through memory: OpenCV refuses YAML without its "%YAML:1.0" first line, which
    // hand-written files often lack; it is added here (and line numbers corrected).
    std::string text = text::readTextFile(path, "projector calibration");
    const std::string_view start =
        std::string_view(text).substr(std::min(text.find_first_not_of(" \t\r\n"), text.size()));
    const std::string extension = lowercaseExtension(path);
    int addedLines = 0;
    if ((extension == ".yml" || extension == ".yaml") && !start.starts_with("%YAML")) {
        text.insert(0, "%YAML:1.0\n");
        addedLines = 1;
    }
    cv::FileStorage storage;
    try {
        if (!storage.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY)) {
            throw InputError(path,
                             "cannot read projector calibration (OpenCV FileStorage YAML, "
                             "XML or JSON expected)");
        }
    } catch (const cv::Exception& failure) {
        throw parseError(path, failure, addedLines);
    }
    const CalibrationReader reader(path, storage);
    ProjectorCalibration c;

    const Numbers k = reader.required("proj_K");
    if (k.values.size() != 9 || (k.rows != 3 && k.rows != 1)) {
        throw InputError(path, "proj_K: expected a 3x3 matrix, found " + shape(k));
    }
    std::copy(k.values.begin(), k.values.end(), c.K.begin());

    if (const auto kc = reader.numbers("proj_kc")) {
        const std::size_t n = kc->values.size();
        if ((kc->rows != 1 && kc->cols != 1) ||
            (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)) {
            throw InputError(path,
                             "proj_kc: expected 4 or 5 distortion coefficients (k1 k2 p1 "
                             "p2 [k3]), found " +
                                 shape(*kc));
        }
        for (std::size_t i = 5; i < n; ++i) {
            if (kc->values[i] != 0) {
                throw InputError(path, "proj_kc: coefficient " + std::to_string(i + 1) +
                                           " is not zero; vpe models k1 k2 p1 p2 k3 only "
                                           "(no rational or thin-prism terms)");
            }
        }
        std::copy_n(kc->values.begin(), std::min<std::size_t>(n, 5), c.distortion.begin());
    }

    const Numbers r = reader.required("R");
    if (r.values.size() == 9 && (r.rows == 3 || r.rows == 1)) {
        std::copy(r.values.begin(), r.values.end(), c.R.begin());
    } else if (r.values.size() == 3 && (r.rows == 1 || r.cols == 1)) {
        c.R = rotationFromVector(r.values);
    } else {
        throw InputError(path,
                         "R: expected a 3x3 rotation matrix or a 3-vector, found " + shape(r));
    }

    const Numbers t = reader.required("T");
    if (t.values.size() != 3 || (t.rows != 1 && t.cols != 1)) {
        throw InputError(path, "T: expected a 3-vector, found " + shape(t));
    }
    std::optional<double> scale = overrides.metresPerUnit;
    if (!scale) {
        if (const auto unit = reader.string("length_unit")) {
            scale = metresPerUnitOf(*unit);
            if (!scale) {
                throw InputError(path, "length_unit: '" + *unit + "' is not m, cm or mm");
            }
        }
    }
    if (scale && (!(*scale > 0) || !std::isfinite(*scale))) {
        throw InputError(path, "T: the unit scale must be a positive number of metres");
    }
    for (std::size_t i = 0; i < 3; ++i) {
        c.T[i] = t.values[i] * scale.value_or(1.0);
    }

    // The resolution: from the file (procam tools disagree on the name) or the overrides.
    std::optional<int> width, height;
    const char* widthKey = nullptr;
    for (const auto& [w, h] :
         {std::pair{"proj_width", "proj_height"}, std::pair{"image_width", "image_height"}}) {
        if (reader.has(w) || reader.has(h)) {
            widthKey = w;
            width = reader.integer(w);
            height = reader.integer(h);
            if (!width || !height) {
                throw InputError(path, std::string(width ? h : w) + ": missing (given " +
                                           (width ? w : h) + " without it)");
            }
            break;
        }
    }
    if (overrides.width.has_value() != overrides.height.has_value()) {
        throw InputError(path, "the projector resolution needs both a width and a height");
    }
    if (width && overrides.width && (*width != *overrides.width || *height != *overrides.height)) {
        throw InputError(path, std::string(widthKey) + ": the file says " + std::to_string(*width) +
                                   "x" + std::to_string(*height) + " but " +
                                   std::to_string(*overrides.width) + "x" +
                                   std::to_string(*overrides.height) + " was given");
    }
    if (!width) {
        if (!overrides.width) {
            throw InputError(path,
                             "no projector resolution (keys proj_width/proj_height or "
                             "image_width/image_height): give it on the command line");
        }
        width = overrides.width;
        height = overrides.height;
    }
    c.width = *width;
    c.height = *height;

    validateProjectorCalibration(c, path);
    if (!scale) {
        const Vec3d centre = c.center();
        const double distance = std::sqrt(proto::dot(centre, centre));
        if (distance > kMaxUnitlessDistance) {
            throw InputError(path, "T: the projector would be " + formatNumber(distance) +
                                       " m from the origin; if T is in millimetres (as "
                                       "procam-calibration writes it), give the unit");
        }
    }
    return c;
}

void writeProjectorCalibration(const ProjectorCalibration& c, const std::filesystem::path& path) {
    validateProjectorCalibration(c, path);
    const std::string extension = lowercaseExtension(path);
    if (extension != ".yml" && extension != ".yaml" && extension != ".xml" &&
        extension != ".json") {
        throw InputError(path, "unsupported calibration format '" + path.extension().string() +
                                   "' (.yml, .yaml, .xml or .json)");
    }
    AtomicOutput output(path);
    try {
        cv::FileStorage storage(output.temporaryPath().string(), cv::FileStorage::WRITE);
        if (!storage.isOpened()) {
            throw InputError(path, "cannot write projector calibration");
        }
        if (extension != ".json") {
            storage.writeComment(
                "vpe projector calibration: x_projector = R * x_object + T "
                "(metres); OpenCV pinhole + distortion");
        }
        storage << "proj_width" << c.width << "proj_height" << c.height;
        storage << "proj_K" << cv::Mat(3, 3, CV_64F, const_cast<double*>(c.K.data()));
        storage << "proj_kc" << cv::Mat(1, 5, CV_64F, const_cast<double*>(c.distortion.data()));
        storage << "R" << cv::Mat(3, 3, CV_64F, const_cast<double*>(c.R.data()));
        storage << "T" << cv::Mat(3, 1, CV_64F, const_cast<double*>(c.T.data()));
        storage << "length_unit"
                << "m";
        storage.release();
    } catch (const cv::Exception& failure) {
        throw InputError(path, "cannot write projector calibration: " + oneLine(failure.err));
    }
    output.commit();
}

ProjectorCalibration projectorLookingAt(int width, int height, double verticalFovDegrees,
                                        const Vec3d& eye, const Vec3d& target) {
    if (!(verticalFovDegrees > 0 && verticalFovDegrees < 180)) {
        throw InputError("projector: vertical field of view must be in (0, 180) degrees");
    }
    const Vec3d toTarget{target.x - eye.x, target.y - eye.y, target.z - eye.z};
    if (!(proto::dot(toTarget, toTarget) > 0)) {
        throw InputError("projector: the eye and the target coincide");
    }
    // The pose is proto's (one definition of "looking at": x right, y down, the world's y up
    // in the image).
    ProjectorCalibration c;
    try {
        c = proto::cameraLookingAt(width, height, verticalFovDegrees, eye, target);
    } catch (const std::invalid_argument& error) {
        throw InputError(std::string("projector: ") + error.what());
    }
    validateProjectorCalibration(c, "projector");
    return c;
}

ProjectorCalibration makeDemoProjector(double distance, const Vec3d& target) {
    if (!(distance > 0) || !std::isfinite(distance)) {
        throw InputError("projector: distance must be a positive number of metres");
    }
    return projectorLookingAt(1920, 1080, 30.0, {target.x, target.y, target.z + distance}, target);
}

}  // namespace vpe::scene
