#include "algorithms/classification/crf_smoothing.h"

// Boost's max-flow trips GCC's -Wmaybe-uninitialized once inlined here (not our code).
// CGAL's default implementation (Boost adjacency list) took 2.3 s on seed 004's test
// cloud where the compressed-sparse-row one took 33.0 s (grapebench_classification_perf
// BM_crf); the MaxFlow one (0.8 s) left isolated noise on the grid of
// tests/algorithms/classification/crf_smoothing_test.cpp that the others remove.
#pragma GCC diagnostic push
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <CGAL/boost/graph/alpha_expansion_graphcut.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "algorithms/point_index.h"
#include "synth/config.h"

namespace grapebench {

const ParamTable<CrfParams>& crf_param_table() {
  using P = CrfParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("radius", "m", &P::radius, 0.001, 1,
                "support radius of the pairwise term (seed 004 Sect. 4.2: about 2 in, 1 in for the ripening set)")
          .integer("neighbours", "count", &P::neighbours, 1, 64, "nearest neighbours within the radius joined by edges")
          .real("weight", "-", &P::weight, 0, 100, "Potts penalty per edge of differing labels, in -ln p units")
          .real("min_probability", "-", &P::min_probability, 1e-12, 0.1, "probabilities clamped here before -ln p");
  return table;
}

namespace {

double potts_energy(const std::vector<std::vector<double>>& unary, const std::vector<std::pair<std::size_t, std::size_t>>& edges,
                    const std::vector<std::size_t>& labels, double w) {
  double e = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) e += unary[labels[i]][i];
  for (const auto& [a, b] : edges) e += labels[a] != labels[b] ? w : 0;
  return e;
}

}  // namespace

CrfResult crf_smoothing(const PointCloud& points, const Eigen::MatrixXd& probabilities, const CrfParams& p) {
  const auto n = static_cast<std::size_t>(points.rows());
  if (static_cast<std::size_t>(probabilities.rows()) != n || probabilities.cols() < 1)
    throw InputError("crf_smoothing: " + std::to_string(probabilities.rows()) + " probability rows for " +
                     std::to_string(n) + " points");
  if (!probabilities.allFinite() || !points.allFinite())
    throw InputError("crf_smoothing: a probability or coordinate is not finite");
  const auto k = static_cast<std::size_t>(probabilities.cols());
  CrfResult r;
  r.scores = probabilities;
  r.labels.assign(n, 0);
  if (n == 0) return r;

  // Unaries -ln p, label-major as CGAL's cost matrix wants.
  std::vector<std::vector<double>> unary(k, std::vector<double>(n));
  std::vector<std::size_t> labels(n);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Index best = 0;
    probabilities.row(static_cast<Eigen::Index>(i)).maxCoeff(&best);
    labels[i] = static_cast<std::size_t>(best);
    for (std::size_t c = 0; c < k; ++c)
      unary[c][i] = -std::log(std::max(p.min_probability, probabilities(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c))));
  }
  // Edges: each point to its nearest `neighbours` within the radius, each pair once.
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  {
    const PointIndex index(points);
    for (std::size_t i = 0; i < n; ++i) {
      for (const auto& [j, d2] : index.nearest(points.row(static_cast<Eigen::Index>(i)).transpose(),
                                               static_cast<std::size_t>(p.neighbours) + 1)) {
        if (j == i || d2 >= p.radius * p.radius) continue;
        edges.emplace_back(std::min<std::size_t>(i, j), std::max<std::size_t>(i, j));
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  }
  r.edges = edges.size();
  r.energy_before = potts_energy(unary, edges, labels, p.weight);
  const std::vector<std::size_t> before = labels;
  if (p.weight > 0 && !edges.empty()) {
    const std::vector<double> costs(edges.size(), p.weight);
    CGAL::alpha_expansion_graphcut(edges, costs, unary, labels);
  }
  r.energy_after = potts_energy(unary, edges, labels, p.weight);
  // The continuous score: each point's label distribution given its neighbours' labels.
  std::vector<std::vector<std::size_t>> adjacent(n);
  for (const auto& [a, b] : edges) {
    adjacent[a].push_back(b);
    adjacent[b].push_back(a);
  }
  for (std::size_t i = 0; i < n; ++i) {
    r.labels[i] = static_cast<int>(labels[i]);
    r.changed += labels[i] != before[i];
    std::vector<double> e(k);
    for (std::size_t c = 0; c < k; ++c) {
      double disagree = 0;
      for (std::size_t j : adjacent[i]) disagree += labels[j] != c;
      e[c] = unary[c][i] + p.weight * disagree;
    }
    const double lo = *std::min_element(e.begin(), e.end());
    double sum = 0;
    for (std::size_t c = 0; c < k; ++c) sum += std::exp(-(e[c] - lo));
    for (std::size_t c = 0; c < k; ++c)
      r.scores(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) = std::exp(-(e[c] - lo)) / sum;
  }
  return r;
}

}  // namespace grapebench

#pragma GCC diagnostic pop
