#include "algorithms/size/percentile_box.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace grapebench {

namespace {

// Linear interpolation between the order statistics at rank q (n - 1).
double percentile(std::vector<double>& v, double q) {
  const double rank = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(rank));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const double a = v[lo];
  double b = a;
  if (hi != lo) b = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(lo) + 1, v.end());
  return a + (rank - static_cast<double>(lo)) * (b - a);
}

}  // namespace

PercentileBox percentile_box(const PointCloud& cloud, const PercentileBoxParams& p) {
  require_points(cloud, 2, "percentile_box");
  if (!(p.alpha >= 0 && p.alpha < 0.5)) throw InputError("percentile_box: alpha must lie in [0, 0.5)");
  PercentileBox b;
  std::array<double, 3> e{};
  for (int k = 0; k < 3; ++k) {
    std::vector<double> v(cloud.col(k).data(), cloud.col(k).data() + cloud.rows());
    b.minimum(k) = percentile(v, p.alpha);
    b.maximum(k) = percentile(v, 1 - p.alpha);
    e[static_cast<std::size_t>(k)] = b.maximum(k) - b.minimum(k);
  }
  std::sort(e.begin(), e.end(), std::greater<>());
  b.edges = e;
  b.diagonals = {std::hypot(e[0], e[1]), std::hypot(e[0], e[2]), std::hypot(e[1], e[2])};
  return b;
}

const ParamTable<PercentileBoxParams>& percentile_box_param_table() {
  static const ParamTable<PercentileBoxParams> table = ParamTable<PercentileBoxParams>().real(
      "alpha", "-", &PercentileBoxParams::alpha, 0, 0.499, "percentile fraction (seed 003 Alg. 1 writes 0.02)");
  return table;
}

}  // namespace grapebench
