// SPDX-License-Identifier: MIT
// SynthRTI Multi ground truth: band lines located in the images, merged by contrast across them.
#include "support/synthrti_band_truth.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"

namespace vpe::testing {

namespace {

std::vector<image::FloatImage> readCaptureImages(const std::filesystem::path& path) {
    const capture::Capture capture = capture::openCapture(path);
    std::vector<image::FloatImage> images;
    images.reserve(capture.images.size());
    for (const capture::CaptureImage& image : capture.images) {
        images.push_back(image::readImage(image.file));
        if (images.back().width != images.front().width ||
            images.back().height != images.front().height || images.back().channels < 3) {
            throw common::InputError(image.file, "size or channels differ from the first image");
        }
    }
    if (images.empty()) {
        throw common::InputError(path, "no images");
    }
    return images;
}

// JPEG's 8×8 blocks add an edge every 8 pixels, in phase with the nominal band lines (40 and
// 20 px); removing the profile's 8-periodic part keeps them from attracting the search.
void removeBlockPhase(std::vector<double>& profile) {
    double phase[8] = {};
    int count[8] = {};
    double mean = 0;
    for (std::size_t i = 1; i < profile.size(); ++i) {
        phase[i % 8] += profile[i];
        ++count[i % 8];
        mean += profile[i];
    }
    mean /= static_cast<double>(profile.size() - 1);
    for (std::size_t i = 1; i < profile.size(); ++i) {
        profile[i] -= phase[i % 8] / count[i % 8] - mean;
    }
}

// The position in [centre − search, centre + search] where the profile, smoothed by [1 2 1],
// peaks.
double peakNear(const std::vector<double>& profile, double centre, int search) {
    const int size = static_cast<int>(profile.size());
    const int middle = static_cast<int>(std::lround(centre));
    double best = -1e300;
    int bestAt = std::clamp(middle, 1, size - 1);
    for (int i = std::max(2, middle - search); i <= std::min(size - 2, middle + search); ++i) {
        const double value = profile[static_cast<std::size_t>(i - 1)] +
                             2 * profile[static_cast<std::size_t>(i)] +
                             profile[static_cast<std::size_t>(i + 1)];
        if (value > best) {
            best = value;
            bestAt = i;
        }
    }
    return bestAt;
}

// Evenly spaced lines (offset + scale · k · cell, k = 1..count−1) that best meet the profile's
// peaks: where to start looking for each line. An exhaustive search, small enough.
std::vector<double> fitEvenLines(const std::vector<double>& profile, int count,
                                 const BandGridOptions& options) {
    const double cell = static_cast<double>(profile.size()) / count;
    // A line outside the image scores nothing (a magnified layout may not show all its bands).
    auto at = [&](double position) {
        if (position < 1 || position >= static_cast<double>(profile.size()) - 1) {
            return 0.0;
        }
        const std::size_t i = static_cast<std::size_t>(position);
        const double t = position - static_cast<double>(i);
        return profile[i] * (1 - t) + profile[i + 1] * t;
    };
    double bestScore = -1e300, bestOffset = 0, bestScale = 1;
    for (double scale = options.minScale; scale <= options.maxScale; scale += 0.001) {
        // The first line may lie anywhere within the first band and a half: magnified layouts
        // start with a cut band.
        for (double offset = -cell; offset <= cell / 2; offset += 0.1) {
            double score = 0;
            for (int k = 1; k < count; ++k) {
                score += at(offset + scale * k * cell);
            }
            if (score > bestScore) {
                bestScore = score;
                bestOffset = offset;
                bestScale = scale;
            }
        }
    }
    std::vector<double> lines;
    for (int k = 1; k < count; ++k) {
        lines.push_back(bestOffset + bestScale * k * cell);
    }
    return lines;
}

int countLinesUpTo(const std::vector<BandLine>& lines, int piece, double centre) {
    int count = 0;
    for (const BandLine& line : lines) {
        count += line.pieces[static_cast<std::size_t>(piece)] <= centre ? 1 : 0;
    }
    return count;
}

double median(std::vector<double>& values) {
    const std::size_t middle = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(middle),
                     values.end());
    return values[middle];
}

}  // namespace

int BandGrid::columnOf(int x, int y) const {
    return countLinesUpTo(columnLines, y / pieceLength, x + 0.5);
}

int BandGrid::rowOf(int x, int y) const {
    return countLinesUpTo(rowLines, x / pieceLength, y + 0.5);
}

BandGrid locateBandGrid(const std::vector<std::filesystem::path>& captures,
                        const BandGridOptions& options) {
    BandGrid grid;
    grid.pieceLength = options.pieceLength;
    // shift[piece][p]: how much the images shift across a line at p (between pixels p − 1 and
    // p), within one piece along it — for every image and channel the median, along the
    // piece, of the difference between pixels 2 before and 2 after the line, in absolute
    // value, summed over images, channels and captures. The median ignores the relief's
    // edges, which cross a line here and there, while a band line shifts the whole piece;
    // summing over images counts gloss-only differences, which show in a few of them.
    constexpr int kReach = 2;
    std::vector<std::vector<double>> columnShift, rowShift;
    auto accumulate = [&](const std::vector<image::FloatImage>& images, bool vertical,
                          std::vector<std::vector<double>>& shift) {
        const int size = vertical ? grid.width : grid.height;
        const int length = vertical ? grid.height : grid.width;
        const int pieces = (length + options.pieceLength - 1) / options.pieceLength;
        shift.resize(static_cast<std::size_t>(pieces), std::vector<double>(size, 0.0));
        std::vector<double> differences;
        for (const image::FloatImage& image : images) {
            for (int c = 0; c < 3; ++c) {
                for (int piece = 0; piece < pieces; ++piece) {
                    const int from = piece * options.pieceLength;
                    const int to = std::min(length, from + options.pieceLength);
                    for (int p = kReach; p + kReach - 1 < size; ++p) {
                        differences.clear();
                        for (int a = from; a < to; ++a) {
                            const float before =
                                vertical ? image.at(p - kReach, a, c) : image.at(a, p - kReach, c);
                            const float after = vertical ? image.at(p + kReach - 1, a, c)
                                                         : image.at(a, p + kReach - 1, c);
                            differences.push_back(static_cast<double>(after - before));
                        }
                        shift[static_cast<std::size_t>(piece)][static_cast<std::size_t>(p)] +=
                            std::fabs(median(differences));
                    }
                }
            }
        }
    };
    for (const std::filesystem::path& capture : captures) {
        const std::vector<image::FloatImage> images = readCaptureImages(capture);
        const image::FloatImage& first = images.front();
        if (grid.width == 0) {
            grid.width = first.width;
            grid.height = first.height;
            if (options.columns < 1 || options.rows < 1 || grid.width < 4 * options.columns ||
                grid.height < 4 * options.rows) {
                throw common::InputError(capture, "images too small for the band grid");
            }
        } else if (first.width != grid.width || first.height != grid.height) {
            throw common::InputError(capture, "image size differs from the other captures'");
        }
        if (options.columns > 1) {
            accumulate(images, true, columnShift);
        }
        if (options.rows > 1) {
            accumulate(images, false, rowShift);
        }
    }
    auto locate = [&](std::vector<std::vector<double>>& shift, bool vertical, int count) {
        std::vector<BandLine> lines;
        if (count <= 1) {
            return lines;
        }
        for (std::vector<double>& piece : shift) {
            removeBlockPhase(piece);
        }
        std::vector<double> whole(shift.front().size(), 0.0);
        for (const std::vector<double>& piece : shift) {
            for (std::size_t p = 0; p < whole.size(); ++p) {
                whole[p] += piece[p];
            }
        }
        // The even fit is only a start: on Object2 the texture is not evenly spaced in the
        // image, so each line then takes the nearest peak, up to a third of a band away.
        const double cell = static_cast<double>(vertical ? grid.width : grid.height) / count;
        for (double start : fitEvenLines(whole, count, options)) {
            BandLine line;
            line.position = peakNear(whole, start, static_cast<int>(cell / 3));
            for (const std::vector<double>& piece : shift) {
                line.pieces.push_back(peakNear(piece, line.position, options.pieceSearch));
            }
            lines.push_back(line);
        }
        return lines;
    };
    if (grid.width == 0) {
        throw common::InputError("band grid: no captures");
    }
    grid.columnLines = locate(columnShift, true, options.columns);
    grid.rowLines = locate(rowShift, false, options.rows);
    return grid;
}

LineContrasts measureLineContrasts(const std::filesystem::path& capture, const BandGrid& grid,
                                   const BandMergeOptions& options) {
    const std::vector<image::FloatImage> images = readCaptureImages(capture);
    if (images.front().width != grid.width || images.front().height != grid.height) {
        throw common::InputError(capture, "image size differs from the band grid's");
    }
    // Per piece, image and channel: the median signed difference across the line — relief
    // and shading vary along it alike on both sides, a change of material shifts it all.
    // Per image and channel: the median of its size over the pieces, so a highlight in a few
    // pieces does not count; the line's contrast is the largest of those, because materials
    // that differ only in gloss differ only near the mirror direction, in a few images.
    auto contrast = [&](const BandLine& line, bool vertical) {
        const int length = vertical ? grid.height : grid.width;
        const int limit = vertical ? grid.width : grid.height;
        std::vector<double> differences, pieces;
        double largest = 0;
        for (const image::FloatImage& image : images) {
            for (int c = 0; c < 3; ++c) {
                pieces.clear();
                for (std::size_t piece = 0; piece < line.pieces.size(); ++piece) {
                    const int edge = static_cast<int>(std::ceil(line.pieces[piece]));
                    const int near = edge - options.edgeOffset;
                    const int far = edge + options.edgeOffset - 1;
                    if (near < 0 || far >= limit) {
                        continue;
                    }
                    differences.clear();
                    const int from = static_cast<int>(piece) * grid.pieceLength;
                    for (int i = from; i < std::min(length, from + grid.pieceLength); ++i) {
                        const float a = vertical ? image.at(near, i, c) : image.at(i, near, c);
                        const float b = vertical ? image.at(far, i, c) : image.at(i, far, c);
                        differences.push_back(255.0 * static_cast<double>(a - b));
                    }
                    pieces.push_back(std::fabs(median(differences)));
                }
                if (!pieces.empty()) {
                    largest = std::max(largest, median(pieces));
                }
            }
        }
        return largest;
    };
    LineContrasts contrasts;
    for (const BandLine& line : grid.columnLines) {
        contrasts.columnLines.push_back(contrast(line, true));
    }
    for (const BandLine& line : grid.rowLines) {
        contrasts.rowLines.push_back(contrast(line, false));
    }
    return contrasts;
}

BandTruth labelBands(const BandGrid& grid, const LineContrasts& contrasts, double boundaryLevels) {
    // Merged band of each grid band: it starts a new one after every boundary line.
    auto merge = [&](const std::vector<double>& lineContrasts) {
        std::vector<int> band{0};
        for (double contrast : lineContrasts) {
            band.push_back(band.back() + (contrast >= boundaryLevels ? 1 : 0));
        }
        return band;
    };
    const std::vector<int> column = merge(contrasts.columnLines);
    const std::vector<int> row = merge(contrasts.rowLines);
    BandTruth truth;
    truth.materialColumns = column.back() + 1;
    truth.materialRows = row.back() + 1;
    truth.materials = truth.materialColumns * truth.materialRows;
    if (truth.materials > 255) {
        throw common::InputError("band grid: more than 255 materials");
    }
    truth.labels.resize(static_cast<std::size_t>(grid.width) * grid.height);
    for (int y = 0; y < grid.height; ++y) {
        for (int x = 0; x < grid.width; ++x) {
            truth.labels[static_cast<std::size_t>(y) * grid.width + x] = static_cast<std::uint8_t>(
                row[static_cast<std::size_t>(grid.rowOf(x, y))] * truth.materialColumns +
                column[static_cast<std::size_t>(grid.columnOf(x, y))]);
        }
    }
    return truth;
}

}  // namespace vpe::testing
