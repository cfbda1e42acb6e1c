// SPDX-License-Identifier: MIT
// k-means clustering of feature vectors: k-means++ seeding, Lloyd iterations, several restarts
// keeping the tightest, all driven by one seed so a result repeats exactly. And the choice of
// K by the silhouette, for segmentation without seeds (the paper's future work).
#pragma once

#include <cstdint>
#include <vector>

namespace vpe::segment {

struct KMeansOptions {
    int clusters = 2;
    int restarts = 5;
    int maxIterations = 100;
    std::uint64_t seed = 1;
    // Centroids are fitted on at most this many points, drawn at random (with the seed): a
    // sample this size places them within noise of the full fit, and bounds the work on
    // multi-megapixel models. Every point is then assigned to its nearest centroid.
    std::size_t maxSamples = 100000;
    unsigned threads = 1;
};

// Points are rows of `dims` floats.
struct KMeansResult {
    int clusters = 0;
    int dims = 0;
    std::vector<double> centroids;  // [cluster][dim]
    double inertia = 0;             // mean squared distance to the centroid, on the fitted points
    std::vector<int> labels;        // [point], nearest centroid
};

KMeansResult kMeans(const std::vector<float>& points, int dims, const KMeansOptions& options);

// Labels every point with its nearest centroid (ties: the lower index).
std::vector<int> nearestCentroids(const std::vector<float>& points, int dims,
                                  const std::vector<double>& centroids, unsigned threads);

struct ClusterCountChoice {
    int chosen = 0;
    std::vector<int> candidates;
    std::vector<double> silhouettes;  // mean silhouette of each candidate
    KMeansResult result;              // the chosen K's clustering
};

// Clusters with every K in [minClusters, maxClusters] and keeps the K with the highest mean
// silhouette (ties: the smaller K), measured on a random subsample of `silhouetteSamples`
// points. The silhouette compares each point's mean distance to its own cluster with that to
// the nearest other one, so it rewards compact, well-separated clusters and, unlike the
// inertia, does not improve just because K grows.
ClusterCountChoice chooseClusterCount(const std::vector<float>& points, int dims, int minClusters,
                                      int maxClusters, const KMeansOptions& options,
                                      std::size_t silhouetteSamples = 3000);

// Mean silhouette of labelled points (Euclidean distances); points alone in their cluster
// count 0.
double meanSilhouette(const std::vector<float>& points, int dims, const std::vector<int>& labels);

}  // namespace vpe::segment
