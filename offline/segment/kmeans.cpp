// SPDX-License-Identifier: MIT
// k-means++ with restarts, and the silhouette choice of K.
#include "vpe/segment/kmeans.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "vpe/common/parallel_for.h"

namespace vpe::segment {

namespace {

constexpr std::size_t kGrain = 4096;

// SplitMix64: tiny, and its output is fixed by the standard-free arithmetic below, so a seed
// gives the same clustering on every platform (std:: distributions are not specified that
// tightly).
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
    std::size_t below(std::size_t n) {
        return static_cast<std::size_t>(uniform() * static_cast<double>(n)) % n;
    }

private:
    std::uint64_t state_;
};

double squaredDistance(const float* point, const double* centroid, int dims) {
    double sum = 0;
    for (int d = 0; d < dims; ++d) {
        const double v = static_cast<double>(point[d]) - centroid[d];
        sum += v * v;
    }
    return sum;
}

// A random subset of [0, count) of at most `size` indices, ascending.
std::vector<std::size_t> sampleIndices(std::size_t count, std::size_t size, Random& random) {
    std::vector<std::size_t> indices(count);
    std::iota(indices.begin(), indices.end(), 0);
    if (count <= size) {
        return indices;
    }
    for (std::size_t i = 0; i < size; ++i) {  // partial Fisher–Yates
        std::swap(indices[i], indices[i + random.below(count - i)]);
    }
    indices.resize(size);
    std::sort(indices.begin(), indices.end());
    return indices;
}

struct Assignment {
    std::vector<int> labels;
    std::vector<double> distances;  // squared, to the assigned centroid
};

void assign(const std::vector<float>& points, int dims, const std::vector<double>& centroids,
            unsigned threads, Assignment& out) {
    const std::size_t count = points.size() / static_cast<std::size_t>(dims);
    const int clusters = static_cast<int>(centroids.size()) / dims;
    out.labels.resize(count);
    out.distances.resize(count);
    common::parallelFor(count, kGrain, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const float* point = &points[i * static_cast<std::size_t>(dims)];
            double best = std::numeric_limits<double>::infinity();
            int bestCluster = 0;
            for (int c = 0; c < clusters; ++c) {
                const double d =
                    squaredDistance(point, &centroids[static_cast<std::size_t>(c) * dims], dims);
                if (d < best) {
                    best = d;
                    bestCluster = c;
                }
            }
            out.labels[i] = bestCluster;
            out.distances[i] = best;
        }
    });
}

// One k-means run on `points` from a k-means++ start.
KMeansResult runOnce(const std::vector<float>& points, int dims, int clusters, int maxIterations,
                     Random& random, unsigned threads) {
    const std::size_t count = points.size() / static_cast<std::size_t>(dims);
    const std::size_t stride = static_cast<std::size_t>(dims);
    KMeansResult result;
    result.clusters = clusters;
    result.dims = dims;
    result.centroids.assign(static_cast<std::size_t>(clusters) * stride, 0.0);
    auto setCentroid = [&](int c, std::size_t point) {
        for (int d = 0; d < dims; ++d) {
            result.centroids[static_cast<std::size_t>(c) * stride + static_cast<std::size_t>(d)] =
                static_cast<double>(points[point * stride + static_cast<std::size_t>(d)]);
        }
    };
    // k-means++: each next centroid is a point drawn with probability ∝ its squared distance
    // to the nearest centroid so far — spread-out starts, a provably good one in expectation.
    setCentroid(0, random.below(count));
    std::vector<double> nearest(count);
    for (std::size_t i = 0; i < count; ++i) {
        nearest[i] = squaredDistance(&points[i * stride], result.centroids.data(), dims);
    }
    for (int c = 1; c < clusters; ++c) {
        const double total = std::accumulate(nearest.begin(), nearest.end(), 0.0);
        std::size_t chosen = count - 1;
        if (total > 0) {
            double target = random.uniform() * total;
            for (std::size_t i = 0; i < count; ++i) {
                target -= nearest[i];
                if (target < 0) {
                    chosen = i;
                    break;
                }
            }
        } else {
            chosen = random.below(count);  // every point sits on a centroid already
        }
        setCentroid(c, chosen);
        const double* centroid = &result.centroids[static_cast<std::size_t>(c) * stride];
        for (std::size_t i = 0; i < count; ++i) {
            nearest[i] = std::min(nearest[i], squaredDistance(&points[i * stride], centroid, dims));
        }
    }
    // Lloyd iterations until no point changes cluster.
    Assignment current;
    std::vector<int> previous;
    std::vector<double> sums(result.centroids.size());
    std::vector<std::size_t> sizes(static_cast<std::size_t>(clusters));
    for (int iteration = 0; iteration < maxIterations; ++iteration) {
        assign(points, dims, result.centroids, threads, current);
        if (current.labels == previous) {
            break;
        }
        previous = current.labels;
        std::fill(sums.begin(), sums.end(), 0.0);
        std::fill(sizes.begin(), sizes.end(), 0);
        for (std::size_t i = 0; i < count; ++i) {
            const std::size_t c = static_cast<std::size_t>(current.labels[i]);
            ++sizes[c];
            for (int d = 0; d < dims; ++d) {
                sums[c * stride + static_cast<std::size_t>(d)] +=
                    static_cast<double>(points[i * stride + static_cast<std::size_t>(d)]);
            }
        }
        for (int c = 0; c < clusters; ++c) {
            const std::size_t size = sizes[static_cast<std::size_t>(c)];
            if (size == 0) {
                // An empty cluster restarts at the point worst served, which splits the
                // loosest cluster instead of wasting a label.
                const std::size_t worst = static_cast<std::size_t>(
                    std::max_element(current.distances.begin(), current.distances.end()) -
                    current.distances.begin());
                setCentroid(c, worst);
                current.distances[worst] = 0;
                continue;
            }
            for (int d = 0; d < dims; ++d) {
                const std::size_t at =
                    static_cast<std::size_t>(c) * stride + static_cast<std::size_t>(d);
                result.centroids[at] = sums[at] / static_cast<double>(size);
            }
        }
    }
    assign(points, dims, result.centroids, threads, current);
    result.inertia = std::accumulate(current.distances.begin(), current.distances.end(), 0.0) /
                     static_cast<double>(count);
    return result;
}

}  // namespace

std::vector<int> nearestCentroids(const std::vector<float>& points, int dims,
                                  const std::vector<double>& centroids, unsigned threads) {
    Assignment assignment;
    assign(points, dims, centroids, threads, assignment);
    return std::move(assignment.labels);
}

KMeansResult kMeans(const std::vector<float>& points, int dims, const KMeansOptions& options) {
    const std::size_t count = points.size() / static_cast<std::size_t>(dims);
    if (options.clusters < 1 || count < static_cast<std::size_t>(options.clusters)) {
        throw std::invalid_argument("k-means: fewer points than clusters");
    }
    Random sampler(options.seed ^ 0x5EED5A3B1E5ull);
    const std::vector<std::size_t> indices = sampleIndices(count, options.maxSamples, sampler);
    std::vector<float> sample;
    sample.reserve(indices.size() * static_cast<std::size_t>(dims));
    for (std::size_t i : indices) {
        const float* point = &points[i * static_cast<std::size_t>(dims)];
        sample.insert(sample.end(), point, point + dims);
    }
    KMeansResult best;
    for (int restart = 0; restart < std::max(1, options.restarts); ++restart) {
        Random random(options.seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(restart));
        KMeansResult result =
            runOnce(sample, dims, options.clusters, options.maxIterations, random, options.threads);
        if (restart == 0 || result.inertia < best.inertia) {
            best = std::move(result);
        }
    }
    best.labels = nearestCentroids(points, dims, best.centroids, options.threads);
    return best;
}

double meanSilhouette(const std::vector<float>& points, int dims, const std::vector<int>& labels) {
    const std::size_t count = labels.size();
    if (count < 2) {
        return 0;
    }
    const int clusters = *std::max_element(labels.begin(), labels.end()) + 1;
    std::vector<std::size_t> sizes(static_cast<std::size_t>(clusters), 0);
    for (int label : labels) {
        ++sizes[static_cast<std::size_t>(label)];
    }
    double total = 0;
    std::vector<double> sums(static_cast<std::size_t>(clusters));
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t own = static_cast<std::size_t>(labels[i]);
        if (sizes[own] < 2) {
            continue;  // a point alone in its cluster scores 0
        }
        std::fill(sums.begin(), sums.end(), 0.0);
        const float* a = &points[i * static_cast<std::size_t>(dims)];
        for (std::size_t j = 0; j < count; ++j) {
            const float* b = &points[j * static_cast<std::size_t>(dims)];
            double d2 = 0;
            for (int d = 0; d < dims; ++d) {
                const double v = static_cast<double>(a[d]) - static_cast<double>(b[d]);
                d2 += v * v;
            }
            sums[static_cast<std::size_t>(labels[j])] += std::sqrt(d2);
        }
        const double within = sums[own] / static_cast<double>(sizes[own] - 1);
        double between = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < sums.size(); ++c) {
            if (c != own && sizes[c] > 0) {
                between = std::min(between, sums[c] / static_cast<double>(sizes[c]));
            }
        }
        if (std::isfinite(between) && std::max(within, between) > 0) {
            total += (between - within) / std::max(within, between);
        }
    }
    return total / static_cast<double>(count);
}

ClusterCountChoice chooseClusterCount(const std::vector<float>& points, int dims, int minClusters,
                                      int maxClusters, const KMeansOptions& options,
                                      std::size_t silhouetteSamples) {
    const std::size_t count = points.size() / static_cast<std::size_t>(dims);
    maxClusters = std::min<int>(maxClusters, static_cast<int>(std::min<std::size_t>(count, 255)));
    if (minClusters < 1 || maxClusters < minClusters) {
        throw std::invalid_argument("k-means: no cluster count to choose from");
    }
    // One subsample for every K, so their silhouettes compare like with like.
    Random sampler(options.seed ^ 0x51E7A3E77Eull);
    const std::vector<std::size_t> indices = sampleIndices(count, silhouetteSamples, sampler);
    std::vector<float> sample;
    for (std::size_t i : indices) {
        const float* point = &points[i * static_cast<std::size_t>(dims)];
        sample.insert(sample.end(), point, point + dims);
    }
    ClusterCountChoice choice;
    double best = -std::numeric_limits<double>::infinity();
    for (int k = minClusters; k <= maxClusters; ++k) {
        KMeansOptions run = options;
        run.clusters = k;
        KMeansResult result = kMeans(points, dims, run);
        std::vector<int> labels;
        labels.reserve(indices.size());
        for (std::size_t i : indices) {
            labels.push_back(result.labels[i]);
        }
        const double silhouette = meanSilhouette(sample, dims, labels);
        choice.candidates.push_back(k);
        choice.silhouettes.push_back(silhouette);
        if (silhouette > best) {
            best = silhouette;
            choice.chosen = k;
            choice.result = std::move(result);
        }
    }
    return choice;
}

}  // namespace vpe::segment
