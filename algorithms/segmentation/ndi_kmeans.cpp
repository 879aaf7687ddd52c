#include "algorithms/segmentation/ndi_kmeans.h"

#include "synth/config.h"
#include "synth/rng.h"

#include <cmath>
#include <limits>
#include <string>

namespace grapebench {

namespace {

double contrast(int a, int b) { return a + b == 0 ? 0.0 : static_cast<double>(a - b) / (a + b); }

// Index of the nearest centroid and the squared distance to it (lowest index on ties).
std::pair<int, double> nearest(const Vec3& x, const std::vector<Vec3>& centroids) {
  int best = 0;
  double d2 = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < centroids.size(); ++c) {
    const double d = (x - centroids[c]).squaredNorm();
    if (d < d2) {
      d2 = d;
      best = static_cast<int>(c);
    }
  }
  return {best, d2};
}

}  // namespace

Vec3 ndi(const Rgb8& c) {
  const int r = c[0], g = c[1], b = c[2];
  return {contrast(r, g), contrast(r, b), contrast(b, g)};
}

std::vector<Vec3> ndi(const std::vector<Rgb8>& rgb) {
  std::vector<Vec3> out(rgb.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) out[i] = ndi(rgb[i]);
  return out;
}

KMeansResult kmeans_pp(const std::vector<Vec3>& x, const KMeansParams& p) {
  if (p.clusters < 1 || p.clusters > 64) {
    throw InputError("kmeans_pp: clusters = " + std::to_string(p.clusters) + " outside [1, 64]");
  }
  if (p.max_iterations < 1 || p.max_iterations > 10000) {
    throw InputError("kmeans_pp: max_iterations = " + std::to_string(p.max_iterations) + " outside [1, 10000]");
  }
  const std::size_t n = x.size(), k = static_cast<std::size_t>(p.clusters);
  if (n < k) {
    throw InputError("kmeans_pp: " + std::to_string(n) + " points for " + std::to_string(k) + " clusters");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!x[i].allFinite()) throw InputError("kmeans_pp: feature " + std::to_string(i) + " is not finite");
  }

  // k-means++ seeding: the first centre uniformly, each next one with probability
  // proportional to the squared distance to the nearest centre chosen so far.
  Rng rng(p.seed);
  KMeansResult r;
  r.centroids.push_back(x[static_cast<std::size_t>(rng.uniform_int(0, static_cast<int>(n) - 1))]);
  std::vector<double> d2(n);
  for (std::size_t i = 0; i < n; ++i) d2[i] = (x[i] - r.centroids[0]).squaredNorm();
  while (r.centroids.size() < k) {
    double total = 0;
    for (double v : d2) total += v;
    std::size_t pick = n - 1;
    if (total > 0) {
      double target = rng.uniform() * total;
      for (std::size_t i = 0; i < n; ++i) {
        target -= d2[i];
        if (target < 0) {
          pick = i;
          break;
        }
      }
    } else {
      // Fewer distinct points than clusters: any point; the duplicate centre ends empty.
      pick = static_cast<std::size_t>(rng.uniform_int(0, static_cast<int>(n) - 1));
    }
    r.centroids.push_back(x[pick]);
    for (std::size_t i = 0; i < n; ++i) d2[i] = std::min(d2[i], (x[i] - x[pick]).squaredNorm());
  }

  // Lloyd iterations.
  r.label.assign(n, -1);
  for (r.iterations = 1; r.iterations <= p.max_iterations; ++r.iterations) {
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      const auto [c, dist] = nearest(x[i], r.centroids);
      d2[i] = dist;
      if (c != r.label[i]) {
        r.label[i] = c;
        changed = true;
      }
    }
    if (!changed) {
      r.converged = true;
      break;
    }
    std::vector<Vec3> sum(k, Vec3::Zero());
    std::vector<std::size_t> count(k, 0);
    for (std::size_t i = 0; i < n; ++i) {
      sum[static_cast<std::size_t>(r.label[i])] += x[i];
      ++count[static_cast<std::size_t>(r.label[i])];
    }
    for (std::size_t c = 0; c < k; ++c) {
      if (count[c] > 0) {
        r.centroids[c] = sum[c] / static_cast<double>(count[c]);
        continue;
      }
      // MATLAB's 'singleton': restart an emptied cluster at the point farthest from
      // its centroid.
      std::size_t far = 0;
      for (std::size_t i = 1; i < n; ++i) {
        if (d2[i] > d2[far]) far = i;
      }
      if (d2[far] > 0) {
        r.centroids[c] = x[far];
        d2[far] = 0;
      }
    }
  }
  r.iterations = std::min(r.iterations, p.max_iterations);
  r.sizes.assign(k, 0);
  r.inertia = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ++r.sizes[static_cast<std::size_t>(r.label[i])];
    r.inertia += (x[i] - r.centroids[static_cast<std::size_t>(r.label[i])]).squaredNorm();
  }
  return r;
}

}  // namespace grapebench
