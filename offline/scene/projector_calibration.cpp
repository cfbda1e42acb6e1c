// SPDX-License-Identifier: MIT
// Projector calibration files through OpenCV's FileStorage.
//
// Two layouts of keys. vpe's are Moreno & Taubin's procam-calibration's (Brown University,
// 2012; CalibrationData::save_calibration_yml):
//   cam_K, cam_kc, proj_K, proj_kc, R, T, cam_error, proj_error, stereo_error
// where R, T come from cv::stereoCalibrate(camera, projector): camera → projector
// coordinates, T in the chessboard's unit; proj_kc has OpenCV's five coefficients (k3 fixed
// at 0 by CALIB_FIX_K3). It does not write the projector's resolution, nor the camera's:
// vpe's files add proj_width/proj_height and cam_width/cam_height (and length_unit).
// kamino410/procam-calibration's calibrate.py writes calibration_result.xml:
//   img_shape (the camera image's rows, cols), rms (cv::stereoCalibrate's), cam_int, cam_dist,
//   proj_int, proj_dist, rotation, translation
// (its first versions spelt rotation "roration"), where rotation, translation are
// cv::stereoCalibrate(camera, projector)'s R, T as well — "from camera coord to projector
// coord", vpe's direction — T in the unit of its chessboard's square size; no projector size.
#include "vpe/scene/projector_calibration.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "vpe/common/input_error.h"
#include "vpe/proto/atomic_file.h"
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
                        throw common::InputError(path_,
                                                 std::string(key) + ": not a list of numbers");
                    }
                    out.values.push_back(static_cast<double>(item));
                }
                out.rows = 1;
                out.cols = static_cast<int>(out.values.size());
            } else {
                cv::Mat matrix;
                node >> matrix;
                if (matrix.empty() || matrix.channels() != 1) {
                    throw common::InputError(path_, std::string(key) + ": not a matrix of numbers");
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
            throw common::InputError(
                path_, std::string(key) + ": not a matrix of numbers (" + oneLine(error.err) + ")");
        }
        for (std::size_t i = 0; i < out.values.size(); ++i) {
            if (!std::isfinite(out.values[i])) {
                throw common::InputError(path_, std::string(key) + ": element " +
                                                    std::to_string(i) + " is not a finite number");
            }
        }
        return out;
    }

    // `needs` says why, in the message: "a projector calibration needs proj_K, R and T".
    Numbers required(const char* key, const char* needs) const {
        auto value = numbers(key);
        if (!value) {
            throw common::InputError(path_, std::string(key) + ": missing (" + needs + ")");
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
        throw common::InputError(path_, std::string(key) + ": expected a whole number of pixels");
    }

    std::optional<std::string> string(const char* key) const {
        const cv::FileNode node = storage_[key];
        if (node.empty() || node.isNone()) {
            return std::nullopt;
        }
        if (!node.isString()) {
            throw common::InputError(path_, std::string(key) + ": expected a string");
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
common::InputError parseError(const std::filesystem::path& path, const cv::Exception& failure,
                              int addedLines, const std::string& what) {
    if (failure.code == cv::Error::StsParseError) {
        const std::string& where = failure.func;
        const std::size_t open = where.rfind('(', where.find("): "));
        const std::size_t close = where.find("): ");
        if (open != std::string::npos && close != std::string::npos && close > open) {
            int line = 0;
            const auto [end, error] =
                std::from_chars(where.data() + open + 1, where.data() + close, line);
            if (error == std::errc() && end == where.data() + close) {
                return common::InputError(
                    path, std::max(1, line - addedLines),
                    "cannot parse " + what + ": " + oneLine(where.substr(close + 3)));
            }
        }
        return common::InputError(path, "cannot parse " + what + ": " + oneLine(where));
    }
    return common::InputError(path, "cannot parse " + what + ": " + oneLine(failure.err));
}

// The keys a pinhole's parts are stored under: the projector's (proj_*) or the camera's
// (cam_*); R and T are the file's own.
struct PinholeKeys {
    const char* what;  // "projector" or "camera", in messages
    const char* K;
    const char* kc;
    const char* width;
    const char* height;
    const char* R = "R";
    const char* T = "T";
};
constexpr PinholeKeys kProjectorKeys{"projector", "proj_K", "proj_kc", "proj_width", "proj_height"};
constexpr PinholeKeys kCameraKeys{"camera", "cam_K", "cam_kc", "cam_width", "cam_height"};

// The keys of a file's layout (the file's comment above): vpe's, or kamino410's.
struct KeyLayout {
    bool vpe = true;
    PinholeKeys projector = kProjectorKeys;
    PinholeKeys camera = kCameraKeys;
    const char* R = "R";
    const char* T = "T";
};

// vpe's keys (Moreno & Taubin's, with what their tool and its forks write beside them);
// kamino410/procam-calibration's; and the keys either may carry: the sizes, T's unit.
constexpr std::array<std::string_view, 13> kVpeKeys = {
    "proj_K",     "proj_kc",      "cam_K", "cam_kc", "R", "T", "cam_error",
    "proj_error", "stereo_error", "E",     "F",      "b", "m"};
constexpr std::array<std::string_view, 9> kToolKeys = {"img_shape", "rms",      "cam_int",
                                                       "cam_dist",  "proj_int", "proj_dist",
                                                       "rotation",  "roration", "translation"};
constexpr std::array<std::string_view, 7> kSharedKeys = {
    "proj_width",  "proj_height",  "cam_width",  "cam_height",
    "image_width", "image_height", "length_unit"};

template <std::size_t N>
bool among(const std::array<std::string_view, N>& keys, const std::string& key) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// The file's layout from its top-level keys. Refuses a key of neither layout, and a file that
// mixes the two (which of proj_K and proj_int would be the projector's?).
KeyLayout layoutOf(const cv::FileStorage& storage, const std::filesystem::path& path) {
    std::vector<std::string> keys;
    const cv::FileNode root = storage.root();
    if (root.isMap()) {
        keys = root.keys();
    }
    std::string unknown, vpeKey, toolKey;
    int unknownCount = 0;
    for (const std::string& key : keys) {
        if (among(kVpeKeys, key)) {
            vpeKey = vpeKey.empty() ? key : vpeKey;
        } else if (among(kToolKeys, key)) {
            toolKey = toolKey.empty() ? key : toolKey;
        } else if (!among(kSharedKeys, key)) {
            unknown += (unknown.empty() ? "" : ", ") + key;
            ++unknownCount;
        }
    }
    if (unknownCount > 0) {
        throw common::InputError(
            path, std::string(unknownCount == 1 ? "unknown key " : "unknown keys ") + unknown +
                      ": neither vpe's calibration keys (proj_K, proj_kc, cam_K, cam_kc, R, T, "
                      "…) nor procam-calibration's calibration_result (proj_int, proj_dist, "
                      "cam_int, cam_dist, rotation, translation, …)");
    }
    if (!vpeKey.empty() && !toolKey.empty()) {
        throw common::InputError(path, "mixes vpe's keys (" + vpeKey +
                                           ") with procam-calibration's calibration_result "
                                           "keys (" +
                                           toolKey + "): one layout per file");
    }
    KeyLayout layout;
    if (toolKey.empty()) {
        return layout;
    }
    const bool rotation = std::find(keys.begin(), keys.end(), "rotation") != keys.end();
    const bool roration = std::find(keys.begin(), keys.end(), "roration") != keys.end();
    if (rotation && roration) {
        throw common::InputError(path,
                                 "roration: given beside rotation (the same key misspelt "
                                 "by the tool's first versions): keep one");
    }
    layout.vpe = false;
    layout.R = roration ? "roration" : "rotation";
    layout.T = "translation";
    layout.projector = {"projector",   "proj_int", "proj_dist", "proj_width",
                        "proj_height", layout.R,   layout.T};
    layout.camera = {"camera",     "cam_int", "cam_dist", "cam_width",
                     "cam_height", layout.R,  layout.T};
    return layout;
}

// The checks a calibration file's pinhole must pass, naming its keys.
void validatePinhole(const proto::PinholeCamera& c, const std::filesystem::path& source,
                     const PinholeKeys& keys) {
    const std::string K = keys.K, kc = keys.kc;
    if (c.width < 1 || c.width > kMaxResolution || c.height < 1 || c.height > kMaxResolution) {
        throw common::InputError(source, std::string(keys.what) + " resolution " +
                                             std::to_string(c.width) + "x" +
                                             std::to_string(c.height) + " is outside 1..8192");
    }
    const auto allFinite = [](const auto& values) {
        return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    };
    if (!allFinite(c.K)) {
        throw common::InputError(source, K + ": not all finite numbers");
    }
    if (!allFinite(c.distortion)) {
        throw common::InputError(source, kc + ": not all finite numbers");
    }
    const std::string R = keys.R, T = keys.T;
    if (!allFinite(c.R)) {
        throw common::InputError(source, R + ": not all finite numbers");
    }
    if (!allFinite(c.T)) {
        throw common::InputError(source, T + ": not all finite numbers");
    }
    if (!(c.K[0] > 0) || !(c.K[4] > 0)) {
        throw common::InputError(
            source, K + ": focal lengths must be positive (fx = " + formatNumber(c.K[0]) +
                        ", fy = " + formatNumber(c.K[4]) + ")");
    }
    if (c.K[3] != 0 || c.K[6] != 0 || c.K[7] != 0 || std::fabs(c.K[8] - 1) > 1e-9) {
        throw common::InputError(source,
                                 K + ": not an intrinsic matrix (expected [fx s cx; 0 fy cy; "
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
        throw common::InputError(source, R + ": not orthonormal (RᵀR differs from I by " +
                                             formatNumber(worst) + ", tolerance 1e-3)");
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    if (std::fabs(det - 1) > kRotationTolerance) {
        throw common::InputError(source, R + ": determinant " + formatNumber(det) +
                                             ", not +1 (a reflection, not a rotation)");
    }
}

// Opens a calibration file into `storage`. Read through memory: OpenCV refuses YAML without its
// "%YAML:1.0" first line, which hand-written files often lack; it is added here (and line
// numbers corrected).
// `what` names the file's kind in messages ("projector calibration"). Returns the file's layout
// (layoutOf: a key of neither is refused).
KeyLayout openCalibration(const std::filesystem::path& path, cv::FileStorage& storage,
                          const std::string& what) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        throw common::InputError(
            path,
            "cannot open " + what +
                (std::filesystem::exists(path, error) ? ": not a regular file" : ": no such file"));
    }
    std::string text = text::readTextFile(path, what);
    const std::string_view start =
        std::string_view(text).substr(std::min(text.find_first_not_of(" \t\r\n"), text.size()));
    const std::string extension = lowercaseExtension(path);
    int addedLines = 0;
    if ((extension == ".yml" || extension == ".yaml") && !start.starts_with("%YAML")) {
        text.insert(0, "%YAML:1.0\n");
        addedLines = 1;
    }
    try {
        if (!storage.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY)) {
            throw common::InputError(
                path, "cannot read " + what + " (OpenCV FileStorage YAML, XML or JSON expected)");
        }
    } catch (const cv::Exception& failure) {
        throw parseError(path, failure, addedLines, what);
    }
    return layoutOf(storage, path);
}

std::array<double, 9> intrinsicsFrom(const Numbers& k, const std::filesystem::path& path,
                                     const char* key) {
    if (k.values.size() != 9 || (k.rows != 3 && k.rows != 1)) {
        throw common::InputError(path,
                                 std::string(key) + ": expected a 3x3 matrix, found " + shape(k));
    }
    std::array<double, 9> K{};
    std::copy(k.values.begin(), k.values.end(), K.begin());
    return K;
}

// OpenCV's k1 k2 p1 p2 [k3 …]; absent: no distortion.
std::array<double, 5> distortionFrom(const CalibrationReader& reader,
                                     const std::filesystem::path& path, const char* key) {
    std::array<double, 5> distortion{};
    if (const auto kc = reader.numbers(key)) {
        const std::size_t n = kc->values.size();
        if ((kc->rows != 1 && kc->cols != 1) ||
            (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)) {
            throw common::InputError(path,
                                     std::string(key) +
                                         ": expected 4 or 5 distortion coefficients (k1 k2 p1 "
                                         "p2 [k3]), found " +
                                         shape(*kc));
        }
        for (std::size_t i = 5; i < n; ++i) {
            if (kc->values[i] != 0) {
                throw common::InputError(path, std::string(key) + ": coefficient " +
                                                   std::to_string(i + 1) +
                                                   " is not zero; vpe models k1 k2 p1 p2 k3 only "
                                                   "(no rational or thin-prism terms)");
            }
        }
        std::copy_n(kc->values.begin(), std::min<std::size_t>(n, 5), distortion.begin());
    }
    return distortion;
}

// R (3×3 or a Rodrigues vector) and T in metres, under the layout's names: T's unit from
// `metresPerUnit` (which must agree with the file's length_unit when it has one), else the
// file's length_unit; nullopt when neither says (T is then taken in metres, and the caller
// judges).
std::optional<double> readPose(const CalibrationReader& reader, const std::filesystem::path& path,
                               std::optional<double> metresPerUnit, proto::PinholeCamera& c,
                               const KeyLayout& layout, const std::string& needs) {
    const std::string R = layout.R, T = layout.T;
    const Numbers r = reader.required(layout.R, needs.c_str());
    if (r.values.size() == 9 && (r.rows == 3 || r.rows == 1)) {
        std::copy(r.values.begin(), r.values.end(), c.R.begin());
    } else if (r.values.size() == 3 && (r.rows == 1 || r.cols == 1)) {
        c.R = rotationFromVector(r.values);
    } else {
        throw common::InputError(
            path, R + ": expected a 3x3 rotation matrix or a 3-vector, found " + shape(r));
    }
    const Numbers t = reader.required(layout.T, needs.c_str());
    if (t.values.size() != 3 || (t.rows != 1 && t.cols != 1)) {
        throw common::InputError(path, T + ": expected a 3-vector, found " + shape(t));
    }
    std::optional<double> scale = metresPerUnit;
    if (const auto unit = reader.string("length_unit")) {
        const std::optional<double> fileScale = metresPerUnitOf(*unit);
        if (!fileScale) {
            throw common::InputError(path, "length_unit: '" + *unit + "' is not m, cm or mm");
        }
        if (scale && *scale != *fileScale) {
            throw common::InputError(path, "length_unit: the file says " + *unit + " but " +
                                               formatNumber(*scale) + " m per unit was given");
        }
        scale = fileScale;
    }
    if (scale && (!(*scale > 0) || !std::isfinite(*scale))) {
        throw common::InputError(path, T + ": the unit scale must be a positive number of metres");
    }
    for (std::size_t i = 0; i < 3; ++i) {
        c.T[i] = t.values[i] * scale.value_or(1.0);
    }
    return scale;
}

// Without a unit, T is metres unless that puts the camera implausibly far: probably millimetres.
void checkUnitlessDistance(const proto::PinholeCamera& c, const std::filesystem::path& path,
                           const char* what, const KeyLayout& layout) {
    const Vec3d centre = c.center();
    const double distance = std::sqrt(proto::dot(centre, centre));
    if (distance > kMaxUnitlessDistance) {
        throw common::InputError(
            path, std::string(layout.T) + ": the " + what + " would be " + formatNumber(distance) +
                      " m from the origin; if it is in millimetres (as procam-calibration writes "
                      "it: the unit of the chessboard's squares), give the unit (length_unit in "
                      "the file, or the command's --calibration-unit)");
    }
}

// A width and height key pair: both or neither.
std::optional<std::pair<int, int>> resolutionFrom(const CalibrationReader& reader,
                                                  const std::filesystem::path& path,
                                                  const char* widthKey, const char* heightKey) {
    if (!reader.has(widthKey) && !reader.has(heightKey)) {
        return std::nullopt;
    }
    const std::optional<int> width = reader.integer(widthKey);
    const std::optional<int> height = reader.integer(heightKey);
    if (!width || !height) {
        throw common::InputError(path, std::string(width ? heightKey : widthKey) +
                                           ": missing (given " + (width ? widthKey : heightKey) +
                                           " without it)");
    }
    return std::pair{*width, *height};
}

cv::Mat matrixOf(const double* values, int rows, int cols) {
    return cv::Mat(rows, cols, CV_64F, const_cast<double*>(values));
}

void writePinhole(cv::FileStorage& storage, const proto::PinholeCamera& c,
                  const PinholeKeys& keys) {
    storage << keys.width << c.width << keys.height << c.height;
    storage << keys.K << matrixOf(c.K.data(), 3, 3);
    storage << keys.kc << matrixOf(c.distortion.data(), 1, 5);
}

// Writes a calibration file atomically: `fill` stores the keys.
void writeCalibrationFile(const std::filesystem::path& path, const char* comment,
                          const std::function<void(cv::FileStorage&)>& fill) {
    const std::string extension = lowercaseExtension(path);
    if (extension != ".yml" && extension != ".yaml" && extension != ".xml" &&
        extension != ".json") {
        throw common::InputError(path, "unsupported calibration format '" +
                                           path.extension().string() +
                                           "' (.yml, .yaml, .xml or .json)");
    }
    proto::AtomicFile output(path);
    try {
        cv::FileStorage storage(output.temporaryPath().string(), cv::FileStorage::WRITE);
        if (!storage.isOpened()) {
            throw common::InputError(path, "cannot write projector calibration");
        }
        if (extension != ".json") {
            storage.writeComment(comment);
        }
        fill(storage);
        storage.release();
    } catch (const cv::Exception& failure) {
        throw common::InputError(path,
                                 "cannot write projector calibration: " + oneLine(failure.err));
    }
    output.commit();
}

bool isOrigin(const proto::PinholeCamera& c) {
    const std::array<double, 9> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
    return c.R == identity && c.T == std::array<double, 3>{};
}

}  // namespace

void validateProjectorCalibration(const ProjectorCalibration& c,
                                  const std::filesystem::path& source) {
    validatePinhole(c, source, kProjectorKeys);
}

void validateCameraCalibration(const proto::PinholeCamera& camera,
                               const std::filesystem::path& source) {
    validatePinhole(camera, source, kCameraKeys);
}

ProjectorCalibration readProjectorCalibration(const std::filesystem::path& path,
                                              const ProjectorCalibrationOverrides& overrides) {
    cv::FileStorage storage;
    const KeyLayout layout = openCalibration(path, storage, "projector calibration");
    const CalibrationReader reader(path, storage);
    ProjectorCalibration c;
    const std::string needs = std::string("a projector calibration needs ") + layout.projector.K +
                              ", " + layout.R + " and " + layout.T;
    c.K = intrinsicsFrom(reader.required(layout.projector.K, needs.c_str()), path,
                         layout.projector.K);
    c.distortion = distortionFrom(reader, path, layout.projector.kc);
    const std::optional<double> scale =
        readPose(reader, path, overrides.metresPerUnit, c, layout, needs);

    // The resolution: from the file (procam tools disagree on the name) or the overrides.
    std::optional<std::pair<int, int>> size;
    const char* widthKey = nullptr;
    for (const auto& [w, h] :
         {std::pair{"proj_width", "proj_height"}, std::pair{"image_width", "image_height"}}) {
        size = resolutionFrom(reader, path, w, h);
        if (size) {
            widthKey = w;
            break;
        }
    }
    if (overrides.width.has_value() != overrides.height.has_value() ||
        overrides.defaultWidth.has_value() != overrides.defaultHeight.has_value()) {
        throw common::InputError(path, "the projector resolution needs both a width and a height");
    }
    if (size && overrides.width &&
        (size->first != *overrides.width || size->second != *overrides.height)) {
        throw common::InputError(
            path, std::string(widthKey) + ": the file says " + std::to_string(size->first) + "x" +
                      std::to_string(size->second) + " but " + std::to_string(*overrides.width) +
                      "x" + std::to_string(*overrides.height) + " was given");
    }
    if (!size && overrides.width) {
        size = std::pair{*overrides.width, *overrides.height};
    }
    if (!size && overrides.defaultWidth) {
        size = std::pair{*overrides.defaultWidth, *overrides.defaultHeight};
    }
    if (!size) {
        throw common::InputError(path,
                                 "no projector resolution (keys proj_width/proj_height or "
                                 "image_width/image_height): give it on the command line");
    }
    c.width = size->first;
    c.height = size->second;

    validatePinhole(c, path, layout.projector);
    if (!scale) {
        checkUnitlessDistance(c, path, "projector", layout);
    }
    return c;
}

// The camera image's size of kamino410's file: img_shape, the image's (rows, cols) as numpy
// gives them (a third number, the channels, is ignored).
std::optional<std::pair<int, int>> imageShapeFrom(const CalibrationReader& reader,
                                                  const std::filesystem::path& path) {
    const std::optional<Numbers> shape = reader.numbers("img_shape");
    if (!shape) {
        return std::nullopt;
    }
    const std::vector<double>& v = shape->values;
    if ((shape->rows != 1 && shape->cols != 1) || (v.size() != 2 && v.size() != 3) ||
        v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) || std::fabs(v[0]) > 1e9 ||
        std::fabs(v[1]) > 1e9) {
        throw common::InputError(path,
                                 "img_shape: expected the camera image's rows and columns, two "
                                 "whole numbers");
    }
    return std::pair{static_cast<int>(v[1]), static_cast<int>(v[0])};
}

std::optional<proto::PinholeCamera> readCameraCalibration(const std::filesystem::path& path,
                                                          CameraPose pose) {
    cv::FileStorage storage;
    const KeyLayout layout = openCalibration(path, storage, "camera calibration");
    const CalibrationReader reader(path, storage);
    const char* K = layout.camera.K;
    const std::optional<Numbers> k = reader.numbers(K);
    if (!k) {
        return std::nullopt;
    }
    proto::PinholeCamera c;
    c.K = intrinsicsFrom(*k, path, K);
    c.distortion = distortionFrom(reader, path, layout.camera.kc);
    auto size = resolutionFrom(reader, path, "cam_width", "cam_height");
    if (!layout.vpe) {
        const auto shape = imageShapeFrom(reader, path);
        if (size && shape && *size != *shape) {
            throw common::InputError(
                path, "cam_width: the file says " + std::to_string(size->first) + "x" +
                          std::to_string(size->second) + " but img_shape says " +
                          std::to_string(shape->first) + "x" + std::to_string(shape->second));
        }
        size = size ? size : shape;
        if (pose == CameraPose::kFromFile) {
            throw common::InputError(path, std::string(layout.R) +
                                               ": procam-calibration's rotation and translation "
                                               "are the projector's pose (camera → projector), "
                                               "not a camera's");
        }
    }
    if (!size) {
        throw common::InputError(path, layout.vpe ? "cam_width: missing (cam_K needs the camera's "
                                                    "resolution: cam_width and cam_height, pixels)"
                                                  : "img_shape: missing (cam_int needs the "
                                                    "camera's resolution: img_shape, or cam_width "
                                                    "and cam_height)");
    }
    c.width = size->first;
    c.height = size->second;
    std::optional<double> scale = 1.0;
    if (pose == CameraPose::kFromFile) {
        scale = readPose(reader, path, std::nullopt, c, layout, "the camera's pose needs R and T");
    }
    validatePinhole(c, path, layout.camera);
    if (!scale) {
        checkUnitlessDistance(c, path, "camera", layout);
    }
    return c;
}

std::optional<double> metresPerLengthUnit(const std::string& unit) {
    return metresPerUnitOf(unit);
}

void writeProjectorCalibration(const ProjectorCalibration& c, const std::filesystem::path& path) {
    writeProcamCalibration(c, std::nullopt, std::nullopt, path);
}

void writeProcamCalibration(const ProjectorCalibration& projector,
                            const std::optional<proto::PinholeCamera>& camera,
                            std::optional<double> stereoRms, const std::filesystem::path& path) {
    validateProjectorCalibration(projector, path);
    if (camera) {
        validateCameraCalibration(*camera, path);
        // The file's R, T are the projector's pose in the camera's frame: a camera elsewhere
        // would have to move the object frame (and the mesh with it), which is not this
        // function's to decide.
        if (!isOrigin(*camera)) {
            throw common::InputError(
                path,
                "cam_K: the camera's pose must be R = I, T = 0 (a procam file's "
                "object frame is the camera's)");
        }
    }
    if (stereoRms && !(std::isfinite(*stereoRms) && *stereoRms >= 0)) {
        throw common::InputError(
            path, "stereo_error: " + formatNumber(*stereoRms) + " is not a finite value ≥ 0");
    }
    const char* comment =
        camera ? "vpe procam calibration: the object frame is the camera's; x_projector = R * "
                 "x_object + T (metres); OpenCV pinhole + distortion"
               : "vpe projector calibration: x_projector = R * x_object + T (metres); OpenCV "
                 "pinhole + distortion";
    writeCalibrationFile(path, comment, [&](cv::FileStorage& storage) {
        writePinhole(storage, projector, kProjectorKeys);
        if (camera) {
            writePinhole(storage, *camera, kCameraKeys);
        }
        storage << "R" << matrixOf(projector.R.data(), 3, 3);
        storage << "T" << matrixOf(projector.T.data(), 3, 1);
        storage << "length_unit"
                << "m";
        if (stereoRms) {
            storage << "stereo_error" << *stereoRms;
        }
    });
}

void writeCameraCalibration(const proto::PinholeCamera& camera, const std::filesystem::path& path) {
    validateCameraCalibration(camera, path);
    writeCalibrationFile(path,
                         "vpe camera calibration: x_camera = R * x_object + T (metres); OpenCV "
                         "pinhole + distortion",
                         [&](cv::FileStorage& storage) {
                             writePinhole(storage, camera, kCameraKeys);
                             storage << "R" << matrixOf(camera.R.data(), 3, 3);
                             storage << "T" << matrixOf(camera.T.data(), 3, 1);
                             storage << "length_unit"
                                     << "m";
                         });
}

ProjectorCalibration projectorLookingAt(int width, int height, double verticalFovDegrees,
                                        const Vec3d& eye, const Vec3d& target) {
    if (!(verticalFovDegrees > 0 && verticalFovDegrees < 180)) {
        throw common::InputError("projector: vertical field of view must be in (0, 180) degrees");
    }
    const Vec3d toTarget{target.x - eye.x, target.y - eye.y, target.z - eye.z};
    if (!(proto::dot(toTarget, toTarget) > 0)) {
        throw common::InputError("projector: the eye and the target coincide");
    }
    // The pose is proto's (one definition of "looking at": x right, y down, the world's y up
    // in the image).
    ProjectorCalibration c;
    try {
        c = proto::cameraLookingAt(width, height, verticalFovDegrees, eye, target);
    } catch (const std::invalid_argument& error) {
        throw common::InputError(std::string("projector: ") + error.what());
    }
    validateProjectorCalibration(c, "projector");
    return c;
}

ProjectorCalibration makeDemoProjector(double distance, const Vec3d& target) {
    if (!(distance > 0) || !std::isfinite(distance)) {
        throw common::InputError("projector: distance must be a positive number of metres");
    }
    return projectorLookingAt(1920, 1080, 30.0, {target.x, target.y, target.z + distance}, target);
}

}  // namespace vpe::scene
