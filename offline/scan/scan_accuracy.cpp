// SPDX-License-Identifier: MIT
// The scan against the simulator's truth.
#include "vpe/scan/scan_accuracy.h"

#include <algorithm>
#include <cmath>

#include "vpe/common/input_error.h"
#include "vpe/common/quantile.h"
#include "vpe/image/image_file.h"

namespace vpe::scan {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A pixel placed to better than this (σ, projector pixels) is a surface point
// (TriangulationOptions::maxSigma); coarser ones were placed by their Gray bin alone.
constexpr double kFinePrecisionPx = 1.0;

}  // namespace

ScanAccuracy compareWithTruth(const structured_light::DecodedScan& decoded,
                              const ProjectorSurface& surface,
                              const std::filesystem::path& truthFolder) {
    const std::filesystem::path cameraPath = truthFolder / "camera-truth.exr";
    const std::filesystem::path projectorPath = truthFolder / "projector-truth.exr";
    const image::FloatImage camera = image::readImageChannels(
        cameraPath, {"projector.x", "projector.y", "centre.x", "centre.y"});
    const image::FloatImage projector = image::readImageChannels(
        projectorPath,
        {"position.X", "position.Y", "position.Z", "normal.X", "normal.Y", "normal.Z", "seen"});
    if (camera.width != decoded.width || camera.height != decoded.height) {
        throw common::InputError(cameraPath, "not the scan's camera size");
    }
    if (projector.width != surface.width || projector.height != surface.height) {
        throw common::InputError(projectorPath, "not the scan's projector size");
    }
    ScanAccuracy a;
    std::vector<double> distances, angles;
    const std::size_t projectorPixels = static_cast<std::size_t>(surface.width) * surface.height;
    for (std::size_t p = 0; p < projectorPixels; ++p) {
        const float* t = &projector.pixels[7 * p];
        const bool measured = !std::isnan(surface.position[3 * p]);
        const bool truth = !std::isnan(t[0]);
        if (t[6] > 0.5f) {
            ++a.seen;
            a.measuredSeen += measured ? 1 : 0;
        }
        if (!measured) {
            continue;
        }
        if (!truth) {
            ++a.measuredWithoutTruth;
            continue;
        }
        const double dx = double(surface.position[3 * p]) - double(t[0]);
        const double dy = double(surface.position[3 * p + 1]) - double(t[1]);
        const double dz = double(surface.position[3 * p + 2]) - double(t[2]);
        distances.push_back(std::sqrt(dx * dx + dy * dy + dz * dz));
        const double cosine = double(surface.normal[3 * p]) * double(t[3]) +
                              double(surface.normal[3 * p + 1]) * double(t[4]) +
                              double(surface.normal[3 * p + 2]) * double(t[5]);
        angles.push_back(std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / kPi);
    }
    a.coverage = a.seen ? double(a.measuredSeen) / double(a.seen) : 0;
    double sum = 0;
    for (const double d : distances) {
        sum += d * d;
    }
    a.depthRmsMm = distances.empty() ? 0 : 1000 * std::sqrt(sum / double(distances.size()));
    a.depthP99Mm = 1000 * common::quantile(distances, 0.99);
    a.normalMedianDeg = common::quantile(angles, 0.5);
    a.normalP95Deg = common::quantile(angles, 0.95);

    double squared = 0;
    std::size_t compared = 0;
    for (std::size_t q = 0; q < decoded.projectorX.size(); ++q) {
        if (std::isnan(decoded.projectorX[q])) {
            continue;
        }
        ++a.decoded;
        const float tx = camera.pixels[4 * q], ty = camera.pixels[4 * q + 1];
        const float cx = camera.pixels[4 * q + 2], cy = camera.pixels[4 * q + 3];
        if (std::isnan(cx) || std::hypot(double(decoded.projectorX[q]) - double(cx),
                                         double(decoded.projectorY[q]) - double(cy)) > 1.0) {
            ++a.wrongAtCentre;
        }
        if (std::isnan(tx)) {
            ++a.decodedWithoutTruth;
            continue;
        }
        const double ex = double(decoded.projectorX[q]) - double(tx),
                     ey = double(decoded.projectorY[q]) - double(ty);
        const double error = std::hypot(ex, ey);
        const bool coarse = !(double(decoded.precision[q]) <= kFinePrecisionPx);
        a.coarseDecodes += coarse ? 1 : 0;
        if (error > 1.0) {
            a.wrongAmongAll += 1;
            a.wrongDecodes += coarse ? 0 : 1;
        }
        // Both axes may be off by their claim: √2 of it along the diagonal.
        const double claim = std::sqrt(2.0) * std::sqrt(3.0) * double(decoded.precision[q]);
        if (!(error <= claim + 1.0)) {
            ++a.wrongCodes;
        }
        const auto source = static_cast<std::size_t>(decoded.source[q]);
        ++a.bySource[source];
        a.rmsBySourcePx[source] += ex * ex + ey * ey;
        squared += ex * ex + ey * ey;
        ++compared;
    }
    for (std::size_t s = 0; s < a.bySource.size(); ++s) {
        a.rmsBySourcePx[s] =
            a.bySource[s] ? std::sqrt(a.rmsBySourcePx[s] / double(a.bySource[s])) : 0;
    }
    for (std::size_t q = 0; q < decoded.projectorX.size(); ++q) {
        if (!std::isnan(camera.pixels[4 * q])) {
            ++a.litSeen;
            a.decodedLitSeen += std::isnan(decoded.projectorX[q]) ? 0 : 1;
        }
    }
    a.litDecodedShare = a.litSeen ? double(a.decodedLitSeen) / double(a.litSeen) : 0;
    a.wrongCodeShare = a.decoded ? double(a.wrongCodes) / double(a.decoded) : 0;
    const std::size_t fine = compared - a.coarseDecodes;
    a.wrongDecodeShare = fine ? double(a.wrongDecodes) / double(fine) : 0;
    a.coarseShare = compared ? double(a.coarseDecodes) / double(compared) : 0;
    a.wrongAmongAllShare = compared ? double(a.wrongAmongAll) / double(compared) : 0;
    a.wrongAtCentreShare = a.decoded ? double(a.wrongAtCentre) / double(a.decoded) : 0;
    a.decodeRmsPx = compared ? std::sqrt(squared / double(compared)) : 0;
    return a;
}

}  // namespace vpe::scan
