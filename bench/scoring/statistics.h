// Uncertainty of the scores and paired comparisons between estimators. The cases of a
// run are paired by design (every estimator measures the same bunches), so two
// estimators are compared on their per-case absolute errors, not on their summaries.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace grapebench {

struct Interval {
  double lo = 0, hi = 0;  // NaN, NaN when it cannot be formed (fewer than 3 pairs)
};

// The central `level` interval of bootstrap values (non-finite ones dropped).
Interval percentile_interval(std::vector<double> values, double level);

// Bootstrap intervals of a scalar output's scores: `resamples` resamplings of the
// (estimate, truth) pairs with replacement, drawn from `seed`, made into BCa intervals
// (bias-corrected and accelerated, Efron and Tibshirani 1993, ch. 14), which hold the
// stated level better than the plain percentile interval for a skewed statistic such
// as the RMSE. Display units as `score()`.
struct ScoreIntervals {
  Interval rmse, bias, mape, r2;
};
ScoreIntervals bootstrap_score_intervals(const std::vector<double>& estimate, const std::vector<double>& truth,
                                         std::uint64_t seed, int resamples = 2000, double level = 0.95);

// Lin's concordance correlation coefficient (Lin 1989, Eq. 2): 2 s_xy / (s_x^2 + s_y^2 +
// (mean_x - mean_y)^2) with 1/n moments; 1 only when estimate = truth for every case.
double concordance(const std::vector<double>& estimate, const std::vector<double>& truth);

// Bland-Altman agreement (Bland and Altman 1986): mean difference estimate - truth and
// the 95 % limits of agreement mean +- 1.96 sd (sd with n - 1).
struct Agreement {
  double mean_difference = 0, lower = 0, upper = 0;
};
Agreement bland_altman(const std::vector<double>& estimate, const std::vector<double>& truth);

// Wilcoxon signed-rank test of paired differences d (zeros dropped, tied |d| given
// their mean rank). Two-sided p: exact (the permutation distribution of the rank sum,
// ties included) up to 50 non-zero differences, else the normal approximation with
// tie and continuity corrections. W+ is the sum of the ranks of the positive d.
struct SignedRankTest {
  int n = 0;  // non-zero differences
  double w_plus = 0, p = 1;
};
SignedRankTest wilcoxon_signed_rank(const std::vector<double>& d);

// Two estimators on the same cases: d_i = |error of A_i| - |error of B_i| (negative:
// A is closer to the truth), its mean with a bootstrap interval, and the Wilcoxon p.
struct PairedComparison {
  int cases = 0;
  double mean_difference = 0;  // mean of d, display units
  Interval interval;           // bootstrap interval of that mean
  SignedRankTest test;
};
// Spatial correlation of an error map: Pearson's r between each value and the one
// `lag` px to its right, over every pair where both exist, pooled over the maps added
// (seed 004: SGBM's signed disparity errors, per view). One r per lag; NaN with fewer
// than 3 pairs or no spread.
class LagCorrelation {
 public:
  explicit LagCorrelation(std::vector<int> lags);
  // map: width x height, row-major; NaN where there is no value.
  void add(const std::vector<float>& map, int width, int height);
  std::vector<double> correlations() const;

 private:
  std::vector<int> lags_;
  std::vector<std::array<double, 6>> sums_;  // per lag: n, sx, sy, sxx, syy, sxy
};

PairedComparison compare_paired(const std::vector<double>& abs_error_a, const std::vector<double>& abs_error_b,
                                std::uint64_t seed, int resamples = 2000, double level = 0.95);

}  // namespace grapebench
