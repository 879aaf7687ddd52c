#include "bench/scoring/points.h"

#include "bench/scoring/scalars.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace grapebench {

PointScore score_points(const std::vector<Vec3>& estimate, const std::vector<Vec3>& truth, double tolerance) {
  if (estimate.size() != truth.size()) throw std::invalid_argument("score_points: estimate and truth sizes differ");
  PointScore s;
  s.cases = static_cast<int>(estimate.size());
  s.tolerance = tolerance;
  std::vector<double> errors;
  Vec3 sum = Vec3::Zero(), sum_sq = Vec3::Zero(), sum_abs = Vec3::Zero();
  double sq = 0;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    if (!estimate[i].allFinite()) continue;
    const Vec3 d = estimate[i] - truth[i];
    errors.push_back(d.norm());
    sq += d.squaredNorm();
    sum += d;
    sum_sq += d.cwiseAbs2();
    sum_abs += d.cwiseAbs();
    s.within += d.norm() <= tolerance;
    s.max_error = std::max(s.max_error, d.norm());
  }
  s.answered = static_cast<int>(errors.size());
  s.success_rate = s.cases > 0 ? static_cast<double>(s.within) / s.cases : std::nan("");
  if (errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.mean_error = s.median_error = s.rmse = s.max_error = nan;
    s.axis_bias = s.axis_rmse = s.axis_mae = {nan, nan, nan};
    return s;
  }
  const double n = static_cast<double>(errors.size());
  double total = 0;
  for (double e : errors) total += e;
  s.mean_error = total / n;
  s.median_error = quantile(errors, 0.5);
  s.rmse = std::sqrt(sq / n);
  for (int k = 0; k < 3; ++k) {
    s.axis_bias[k] = sum[k] / n;
    s.axis_rmse[k] = std::sqrt(sum_sq[k] / n);
    s.axis_mae[k] = sum_abs[k] / n;
  }
  return s;
}

}  // namespace grapebench
