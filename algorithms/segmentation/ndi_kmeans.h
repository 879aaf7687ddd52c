// Colour clustering of seed 003 (Sect. II-B2): the NDI colour space (Eq. 1) and
// k-means with k-means++ seeding (Arthur and Vassilvitskii 2007), as MATLAB's default
// `kmeans` runs it (squared Euclidean distance, at most 100 Lloyd iterations, an
// emptied cluster restarted at the point farthest from its centroid).
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace grapebench {


// Seed 003 Eq. 1: N = (R-G)/(R+G), D = (R-B)/(R+B), I = (B-G)/(B+G), each in [-1, 1].
// A ratio whose denominator is 0 (both channels black) has no contrast and is 0, so
// no NaN reaches the clustering.
Vec3 ndi(const Rgb8& rgb);
std::vector<Vec3> ndi(const std::vector<Rgb8>& rgb);

struct KMeansParams {
  int clusters = 5;           // k, [1, 64]; seed 003: 5 (detection), 3 (separation)
  int max_iterations = 100;   // Lloyd iterations, [1, 10000]; MATLAB's default
  std::uint64_t seed = 1;     // the k-means++ draws; same seed, same result
};

struct KMeansResult {
  std::vector<int> label;            // N: cluster of each point, [0, k)
  std::vector<Vec3> centroids;       // k
  std::vector<std::size_t> sizes;    // k: points per cluster
  int iterations = 0;                // Lloyd iterations run
  bool converged = false;            // no label changed in the last iteration
  double inertia = 0;                // sum of squared distances to the centroids
};

// Deterministic: draws come from `seed` only and the loops run in a fixed order.
// Throws InputError for fewer points than clusters, parameters out of range or
// non-finite features.
KMeansResult kmeans_pp(const std::vector<Vec3>& features, const KMeansParams& params);

}  // namespace grapebench
