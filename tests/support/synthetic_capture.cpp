// SPDX-License-Identifier: MIT
// Synthetic capture writer.
#include "support/synthetic_capture.h"

#include <cmath>
#include <fstream>
#include <random>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

#include "vpe/capture/surface_geometry.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/srgb.h"

namespace vpe::testing {

namespace {

void writeImage(const std::filesystem::path& path, int width, int height,
                const std::vector<float>& rgb, SyntheticFormat format) {
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::TypeDesc type = format == SyntheticFormat::kExr           ? OIIO::TypeDesc::FLOAT
                          : format == SyntheticFormat::kPng16Linear ? OIIO::TypeDesc::UINT16
                                                                    : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(width, height, 3, type);
    std::vector<float> encoded = rgb;
    if (format == SyntheticFormat::kPng8Srgb) {
        for (float& v : encoded) {
            v = static_cast<float>(
                proto::linearToSrgb(std::clamp(static_cast<double>(v), 0.0, 1.0)));
        }
    }
    if (!out || !out->open(path.string(), spec) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, encoded.data()) || !out->close()) {
        throw std::runtime_error("cannot write " + path.string());
    }
}

}  // namespace

std::vector<proto::Vec3d> sphereLights(int count) {
    std::vector<proto::Vec3d> lights;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / count;
        const double r = std::sqrt(1.0 - z * z);
        lights.push_back({r * std::cos(golden * i), r * std::sin(golden * i), z});
    }
    return lights;
}

std::vector<proto::Vec3d> domeLights(const std::vector<double>& elevations, int perRing,
                                     double azimuthOffsetDegrees) {
    std::vector<proto::Vec3d> lights;
    for (double elevation : elevations) {
        const double e = elevation * M_PI / 180;
        for (int i = 0; i < perRing; ++i) {
            const double a = (azimuthOffsetDegrees + 360.0 * i / perRing) * M_PI / 180;
            lights.push_back({std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)});
            if (elevation >= 90) {
                break;
            }
        }
    }
    return lights;
}

SyntheticCapture writeSyntheticCapture(const std::filesystem::path& dir,
                                       const SyntheticCaptureSpec& spec) {
    std::filesystem::create_directories(dir);
    const int w = spec.width;
    const int h = spec.height;
    const int k = proto::coefficientCount(spec.harmonics);
    const std::vector<proto::Vec3d> lights = spec.lights.empty() ? sphereLights(64) : spec.lights;
    SyntheticCapture capture;
    capture.dir = dir;
    capture.coefficientCount = k;
    capture.coefficients.resize(static_cast<std::size_t>(w) * h * 3 * k);
    capture.normals.resize(static_cast<std::size_t>(w) * h);
    std::mt19937 random(spec.seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            proto::Vec3d n;
            if (spec.normal) {
                n = spec.normal(x, y);
            } else {
                n = {0.5 * (x - w / 2.0) / w, 0.5 * (h / 2.0 - y) / h, 1.0};
            }
            capture.normals[static_cast<std::size_t>(y) * w + x] = proto::normalized(n);
            for (int c = 0; c < 3; ++c) {
                double* coefficients = capture.coefficients.data() +
                                       ((static_cast<std::size_t>(y) * w + x) * 3 + c) * k;
                if (spec.coefficients) {
                    spec.coefficients(x, y, c, coefficients);
                } else {
                    coefficients[proto::kLambertIndex] = 0.4 + 0.1 * uniform(random);
                    coefficients[proto::kConstantIndex] = 0.05 + 0.02 * uniform(random);
                    for (int i = 2; i < k; ++i) {
                        coefficients[i] = 0.05 * uniform(random) / proto::harmonicOf(i);
                    }
                }
            }
        }
    }
    const char* extension = spec.format == SyntheticFormat::kExr ? ".exr" : ".png";
    std::vector<std::string> names;
    // The geometry the images are rendered under (the .lp keeps the bare directions).
    capture::Capture stated;
    for (const proto::Vec3d& light : lights) {
        stated.images.push_back({"", light, 1.0, 0});
    }
    const capture::Capture rendered =
        capture::applyGeometryCalibration(stated, spec.geometry, w, h);
    const capture::SurfaceGeometry geometry(rendered, w, h);
    std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t s = 0; s < lights.size(); ++s) {
        const std::string name = "light" + std::to_string(s) + extension;
        names.push_back(name);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * w + x;
                const capture::IncidentLight light =
                    capture::incidentLight(rendered, rendered.images[s], geometry.position(x, y));
                const auto angles = proto::reflectionAngles(capture.normals[p], light.direction,
                                                            geometry.toViewer(x, y));
                const double shadow = spec.transport ? spec.transport(x, y, lights[s]) : 1.0;
                for (int c = 0; c < 3; ++c) {
                    const double tint = spec.tint ? spec.tint(x, y, c, lights[s]) : 1.0;
                    rgb[p * 3 + c] = static_cast<float>(
                        tint * shadow * light.irradiance *
                        proto::evaluateFourierBrdf(capture.at(x, y, c, w), spec.harmonics,
                                                   angles.cosThetaD, angles.cosThetaS));
                }
            }
        }
        writeImage(dir / name, w, h, rgb, spec.format);
    }
    {
        std::ofstream lp(dir / "dirs.lp");
        lp.precision(17);  // exact recovery needs the lights to full precision
        lp << lights.size() << "\n";
        for (std::size_t s = 0; s < lights.size(); ++s) {
            lp << names[s] << " " << lights[s].x << " " << lights[s].y << " " << lights[s].z
               << "\n";
        }
    }
    std::vector<float> normals(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t p = 0; p < capture.normals.size(); ++p) {
        normals[p * 3] = static_cast<float>(capture.normals[p].x);
        normals[p * 3 + 1] = static_cast<float>(capture.normals[p].y);
        normals[p * 3 + 2] = static_cast<float>(capture.normals[p].z);
    }
    if (spec.manifest) {
        writeImage(dir / "normals.exr", w, h, normals, SyntheticFormat::kExr);
        std::ofstream json(dir / "capture.json");
        json.precision(17);
        json << "{\"format\": \"vpe-capture\", \"version\": 1, \"normals\": {\"file\": "
                "\"normals.exr\", \"encoding\": \"raw\"}, \"images\": [";
        for (std::size_t s = 0; s < lights.size(); ++s) {
            json << (s ? ", " : "") << "{\"file\": \"" << names[s] << "\", \"light\": ["
                 << lights[s].x << ", " << lights[s].y << ", " << lights[s].z << "]}";
        }
        json << "]}\n";
    } else {
        std::vector<float> offset(normals.size());
        for (std::size_t i = 0; i < normals.size(); ++i) {
            offset[i] = (normals[i] + 1.0f) * 0.5f;
        }
        writeImage(dir / "normals.png", w, h, offset, SyntheticFormat::kPng16Linear);
    }
    return capture;
}

normals::NormalMap trueNormalMap(const SyntheticCapture& capture, int width, int height) {
    normals::NormalMap map;
    map.resize(width, height);
    for (std::size_t p = 0; p < capture.normals.size(); ++p) {
        map.xyz[p * 3] = static_cast<float>(capture.normals[p].x);
        map.xyz[p * 3 + 1] = static_cast<float>(capture.normals[p].y);
        map.xyz[p * 3 + 2] = static_cast<float>(capture.normals[p].z);
        map.valid[p] = 1;
    }
    return map;
}

}  // namespace vpe::testing
