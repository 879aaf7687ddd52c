// Scores of a 3D point output (seed 001's cutting point) against the exact point:
// Euclidean and per-axis errors over the cases that answered, and the success rate
// within a stated tolerance over all cases.
#pragma once

#include "synth/types.h"

#include <array>
#include <vector>

namespace grapebench {

struct PointScore {
  int cases = 0;      // every case, answered or not
  int answered = 0;   // cases with a finite point
  int within = 0;     // answered cases whose Euclidean error is at most the tolerance
  double tolerance = 0;         // m
  double success_rate = 0;      // within / cases
  double mean_error = 0;        // m, Euclidean, over the answered cases
  double median_error = 0;      // m
  double rmse = 0;              // m, sqrt(mean squared Euclidean error)
  double max_error = 0;         // m
  std::array<double, 3> axis_bias{};  // m, mean signed error per axis (x, y, z)
  std::array<double, 3> axis_rmse{};  // m, per axis
  std::array<double, 3> axis_mae{};   // m, mean absolute error per axis
};

// estimate[i], truth[i]: the case's answer and exact point (m, one frame); a
// non-finite estimate is a case that did not answer. Statistics over no answered
// case are NaN. Throws std::invalid_argument when the sizes differ.
PointScore score_points(const std::vector<Vec3>& estimate, const std::vector<Vec3>& truth, double tolerance);

}  // namespace grapebench
