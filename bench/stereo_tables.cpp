#include "bench/stereo_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace grapebench {

std::pair<double, double> wilson_interval(int k, int n) {
  if (n <= 0) return {NAN, NAN};
  const double z = 1.96, p = static_cast<double>(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4.0 * n)) / (1 + z2n);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

namespace {

// "station_0800mm" -> 800 -> the paper's 100 mm bin; -1 when the name holds no depth.
int depth_bin(const std::string& roi) {
  int mm = 0;
  if (std::sscanf(roi.c_str(), "station_%dmm", &mm) != 1) return -1;
  return (mm + 50) / 100 * 100;
}

}  // namespace

StereoTables stereo_tables(const std::vector<CaseResult>& cases, const std::vector<std::string>& labels) {
  StereoTables t;
  std::map<std::pair<std::string, int>, SuccessCell> success;  // (estimator, condition)
  std::map<std::pair<std::string, int>, DepthCell> depth;      // (estimator, depth)
  std::vector<std::string> order;                              // estimators as met
  for (const CaseResult& c : cases) {
    for (const EstimateRow& r : c.rows) {
      if (std::find(order.begin(), order.end(), r.estimator) == order.end()) order.push_back(r.estimator);
      if (r.quantity == "cut_success" && r.ok) {
        SuccessCell& s = success[{r.estimator, c.condition}];
        s.estimator = r.estimator;
        s.condition = c.condition < static_cast<int>(labels.size()) ? labels[c.condition] : "";
        ++s.pairs;
        s.successes += r.estimate > 0.5;
      }
      const int bin = depth_bin(r.roi);
      if (bin < 0) continue;
      DepthCell& d = depth[{r.estimator, bin}];
      d.estimator = r.estimator;
      d.depth_mm = bin;
      if (r.quantity == "berries_found" && r.ok) {
        ++d.pairs;
        d.visible += static_cast<int>(std::lround(r.truth));
        d.found += static_cast<int>(std::lround(r.estimate));
      }
      if (r.quantity == "cut_z" && r.ok) d.ez_mm += 1e3 * std::abs(r.estimate - r.truth), ++d.answered;
      if (r.quantity == "cut_x" && r.ok) d.ex_mm += 1e3 * std::abs(r.estimate - r.truth);
    }
  }
  for (const std::string& e : order) {
    for (auto& [key, s] : success) {
      if (key.first != e) continue;
      s.rate = s.pairs ? static_cast<double>(s.successes) / s.pairs : NAN;
      std::tie(s.lo, s.hi) = wilson_interval(s.successes, s.pairs);
      t.success.push_back(s);
    }
    for (auto& [key, d] : depth) {
      if (key.first != e) continue;
      if (d.answered) d.ez_mm /= d.answered, d.ex_mm /= d.answered;
      t.depth.push_back(d);
    }
  }
  return t;
}

}  // namespace grapebench
