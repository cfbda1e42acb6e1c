// SPDX-License-Identifier: MIT
// A fitted model exported to Relight's web format, with its round trip measured.
#include "vpe/relight_web/model_relight_export.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/eval/capture_predictor.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/relight_web/openlime_display.h"
#include "vpe/relight_web/relight_web_reader.h"

namespace vpe::relight_web {

namespace {

// The capture with its images replaced by one light towards `towardsLight`. A point-light
// rig gets a light at its reference distance in that direction: the web format only knows
// directions, and that is the light the model's irradiance is normalized to.
capture::Capture underOneLight(const capture::Capture& capture, const proto::Vec3d& towardsLight) {
    capture::Capture single = capture;
    capture::CaptureImage image;
    image.light = capture.lightKind == capture::LightKind::kPoint
                      ? proto::Vec3d{towardsLight.x * capture.lightReferenceDistance,
                                     towardsLight.y * capture.lightReferenceDistance,
                                     towardsLight.z * capture.lightReferenceDistance}
                      : towardsLight;
    image.file = capture.images.empty() ? std::filesystem::path{} : capture.images.front().file;
    single.images = {image};
    return single;
}

// The model's prediction of every valid pixel under each of `capture`'s lights, into
// out[light] (width·height·3, sRGB; invalid pixels black).
void predictAll(const model::ModelInfo& info, const model::ModelRows& rows,
                const capture::Capture& capture, const capture::TransferFunction& stored,
                unsigned threads, std::vector<std::vector<float>>& out) {
    const eval::CapturePredictor predictor(info, capture, stored);
    const int lights = predictor.lightCount();
    out.assign(static_cast<std::size_t>(lights),
               std::vector<float>(static_cast<std::size_t>(info.width) * info.height * 3, 0.0f));
    common::parallelFor(
        static_cast<std::size_t>(info.height), 1, threads, [&](std::size_t begin, std::size_t end) {
            for (std::size_t r = begin; r < end; ++r) {
                const int y = static_cast<int>(r);
                for (int x = 0; x < info.width; ++x) {
                    const std::size_t p = rows.pixel(y, x);
                    if (!rows.valid[p]) {
                        continue;
                    }
                    for (int s = 0; s < lights; ++s) {
                        const std::array<double, 3> rgb = predictor.predict(rows, y, x, y, s);
                        for (int c = 0; c < 3; ++c) {
                            out[static_cast<std::size_t>(s)][p * 3 + c] =
                                static_cast<float>(rgb[static_cast<std::size_t>(c)]);
                        }
                    }
                }
            }
        });
}

// The direction the export is relit from for a capture light (a point light: from the
// middle of the picture's surface, where most of it sits).
proto::Vec3d directionOf(const capture::Capture& capture, const capture::CaptureImage& image) {
    if (capture.lightKind == capture::LightKind::kDirectional) {
        return image.light;
    }
    return capture::unitDirection(image.light).value_or(proto::Vec3d{0, 0, 1});
}

// Every decoded value below 0 at the grid's nodes; between them a light blends four nodes with
// non-negative weights, so the nodes bound the whole light field from below.
NegativeDecodes negativeDecodes(const RelightWebReader& reader) {
    NegativeDecodes negative;
    negative.lowest = std::numeric_limits<double>::infinity();
    const std::size_t pixels = static_cast<std::size_t>(reader.width()) * reader.height();
    std::vector<std::uint8_t> below(pixels, 0);
    for (int node = 0; node < reader.grid().nodeCount(); ++node) {
        const std::vector<float> values = reader.decodeNode(node);
        bool any = false;
        for (std::size_t i = 0; i < values.size(); ++i) {
            if (values[i] < 0.0f) {
                ++negative.values;
                below[i / 3] = 1;
                any = true;
            }
            negative.lowest = std::min(negative.lowest, static_cast<double>(values[i]));
        }
        negative.nodes += any ? 1 : 0;
    }
    for (const std::uint8_t b : below) {
        negative.pixels += b;
    }
    return negative;
}

}  // namespace

RelightModelExport exportModelToRelight(const std::filesystem::path& modelPath,
                                        const capture::Capture& capture,
                                        const std::filesystem::path& folder,
                                        const RelightWebOptions& options,
                                        const capture::Capture& checkLights) {
    model::ModelReader model(modelPath, model::ModelKinds::kAny);
    // The object under an unobstructed light: lights that the capture rig blocked
    // (GeometryCalibration::lightIntensities) are the rig's, not the object's appearance.
    model::ModelInfo info = model.info();
    info.calibration.lightIntensities.clear();
    model::ModelRows rows;
    model.readRows(0, info.height, rows);
    // What the capture's images were stored with (an RTI basis predicts stored values).
    bool eightBit = true;
    {
        capture::ImageBandReader reader(capture, options.threads);
        eightBit = reader.eightBitCodes();
        if (reader.width() != info.width || reader.height() != info.height) {
            throw common::InputError(
                capture.source, "images are " + std::to_string(reader.width()) + "x" +
                                    std::to_string(reader.height()) + " but the model " +
                                    modelPath.string() + " is " + std::to_string(info.width) + "x" +
                                    std::to_string(info.height));
        }
    }
    const capture::TransferFunction stored = capture::storedTransfer(capture, eightBit);

    const LightRenderer render = [&](const proto::Vec3d& towardsLight, std::vector<float>& rgb) {
        std::vector<std::vector<float>> one;
        predictAll(info, rows, underOneLight(capture, towardsLight), stored, options.threads, one);
        rgb = std::move(one.front());
    };
    std::vector<proto::Vec3d> lights;
    for (const capture::CaptureImage& image : capture.images) {
        lights.push_back(directionOf(capture, image));
    }
    RelightModelExport result;
    result.summary = writeRelightWeb(folder, info.width, info.height, render, options, lights);

    // The round trip: the export as OpenLIME relights it against the model's own prediction
    // under each check light, over the pixels with a valid fit.
    const capture::Capture& check = checkLights.images.empty() ? capture : checkLights;
    std::vector<std::vector<float>> predicted;
    predictAll(info, rows, check, stored, options.threads, predicted);
    const RelightWebReader reader(folder);
    std::size_t valid = 0;
    for (const std::uint8_t v : rows.valid) {
        valid += v != 0;
    }
    if (valid == 0) {
        throw common::InputError(modelPath, "no pixel has a valid fit: nothing to export");
    }
    const auto psnrOf = [&](const std::vector<float>& shown, const std::vector<float>& truth) {
        double squared = 0;
        for (std::size_t p = 0; p < rows.valid.size(); ++p) {
            if (!rows.valid[p]) {
                continue;
            }
            for (std::size_t c = 0; c < 3; ++c) {
                const double d = shown[p * 3 + c] - truth[p * 3 + c];
                squared += d * d;
            }
        }
        const double mse = squared / (3.0 * static_cast<double>(valid));
        return mse > 1e-10 ? 10.0 * std::log10(1.0 / mse) : 100.0;
    };
    const auto add = [](LightPsnrs& psnrs, double psnr) {
        psnrs.perLight.push_back(psnr);
        psnrs.worst = psnrs.perLight.size() == 1 ? psnr : std::min(psnrs.worst, psnr);
    };
    RelightRoundTrip& trip = result.roundTrip;
    for (std::size_t s = 0; s < check.images.size(); ++s) {
        std::vector<float> decoded = reader.decode(directionOf(check, check.images[s]));
        std::vector<float> shown = decoded;
        showAsOpenLime(shown);
        for (float& value : decoded) {
            value = std::clamp(value, 0.0f, 1.0f);
        }
        std::vector<float> ceiling = predicted[s];
        showAsOpenLime(ceiling);
        add(trip.viewer, psnrOf(shown, predicted[s]));
        add(trip.decoded, psnrOf(decoded, predicted[s]));
        add(trip.displayOnly, psnrOf(ceiling, predicted[s]));
    }
    for (LightPsnrs* psnrs : {&trip.viewer, &trip.decoded, &trip.displayOnly}) {
        double sum = 0;
        for (const double psnr : psnrs->perLight) {
            sum += psnr;
        }
        psnrs->mean = sum / std::max<std::size_t>(1, psnrs->perLight.size());
    }
    trip.lights = static_cast<int>(check.images.size());
    trip.pixels = valid;
    trip.negative = negativeDecodes(reader);
    return result;
}

}  // namespace vpe::relight_web
