// bench/scoring/statistics: each statistic on a case worked by hand, and the bootstrap's
// coverage in a seeded simulation.
#include "bench/scoring/statistics.h"

#include "synth/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace grapebench {
namespace {

TEST(Statistics, WilcoxonExactMatchesTheHandCount) {
  // |d| ranks 3 1 4 5 2 6; W+ = 3 + 4 + 5 + 6 = 18; P(W+ >= 18) = 5/64 (the subsets of
  // 1..6 summing to 3 or less: {}, {1}, {2}, {3}, {1,2}); two-sided 10/64.
  const SignedRankTest t = wilcoxon_signed_rank({1.5, -0.5, 2, 3, -1, 4});
  EXPECT_EQ(t.n, 6);
  EXPECT_DOUBLE_EQ(t.w_plus, 18);
  EXPECT_DOUBLE_EQ(t.p, 10.0 / 64);
  // Ties: |d| = 1 1 2 2 3 take ranks 1.5 1.5 3.5 3.5 5; W+ = 13.5. Doubled ranks 3 3 7 7
  // 10: sums >= 27 are the complements of sums <= 3 ({}, {3}, {3'}): 3 of 32, p = 6/32.
  const SignedRankTest ties = wilcoxon_signed_rank({1, -1, 2, 2, 3, 0});
  EXPECT_EQ(ties.n, 5);  // the zero is dropped
  EXPECT_DOUBLE_EQ(ties.w_plus, 13.5);
  EXPECT_DOUBLE_EQ(ties.p, 6.0 / 32);
  // All differences one way; symmetric ones give p near 1.
  EXPECT_DOUBLE_EQ(wilcoxon_signed_rank({1, 2, 3, 4, 5}).p, 2.0 / 32);
  EXPECT_EQ(wilcoxon_signed_rank({}).p, 1);
}

TEST(Statistics, WilcoxonNormalApproximationAboveFifty) {
  std::vector<double> one_way, alternating;
  for (int i = 1; i <= 60; ++i) {
    one_way.push_back(i);
    alternating.push_back(i % 2 ? i : -i);
  }
  // W+ = 1830, mean 915, variance 60 x 61 x 121 / 24 = 18452.5: z = 6.73.
  const SignedRankTest t = wilcoxon_signed_rank(one_way);
  EXPECT_DOUBLE_EQ(t.w_plus, 1830);
  EXPECT_NEAR(t.p, std::erfc((915 - 0.5) / std::sqrt(18452.5) / std::sqrt(2.0)), 1e-15);
  EXPECT_GT(wilcoxon_signed_rank(alternating).p, 0.8);
}

TEST(Statistics, ConcordanceAndBlandAltmanByHand) {
  // x = 1 2 3, y = 2 3 4: 1/n moments 2/3, 2/3, 2/3, mean shift 1: 2 (2/3) / (7/3) = 4/7.
  EXPECT_DOUBLE_EQ(concordance({2, 3, 4}, {1, 2, 3}), 4.0 / 7);
  EXPECT_DOUBLE_EQ(concordance({1, 2, 3}, {1, 2, 3}), 1.0);
  EXPECT_TRUE(std::isnan(concordance({5, 5}, {5, 5})));
  // Differences 1 1 2: mean 4/3, sd sqrt(1/3); limits 4/3 -+ 1.96 sqrt(1/3).
  const Agreement a = bland_altman({2, 3, 5}, {1, 2, 3});
  EXPECT_DOUBLE_EQ(a.mean_difference, 4.0 / 3);
  EXPECT_NEAR(a.lower, 4.0 / 3 - 1.96 * std::sqrt(1.0 / 3), 1e-12);
  EXPECT_NEAR(a.upper, 4.0 / 3 + 1.96 * std::sqrt(1.0 / 3), 1e-12);
}

TEST(Statistics, PairedComparisonIsSeededAndCentredOnTheMeanDifference) {
  const std::vector<double> a = {1, 2, 3, 4, 1.5, 2.5}, b = {2, 2, 2, 2, 2, 2};
  const PairedComparison c = compare_paired(a, b, 7);
  EXPECT_EQ(c.cases, 6);
  EXPECT_DOUBLE_EQ(c.mean_difference, (-1 + 0 + 1 + 2 - 0.5 + 0.5) / 6.0);
  EXPECT_LT(c.interval.lo, c.mean_difference);
  EXPECT_GT(c.interval.hi, c.mean_difference);
  // The interval lies within the range of the differences.
  EXPECT_GE(c.interval.lo, -1);
  EXPECT_LE(c.interval.hi, 2);
  const PairedComparison again = compare_paired(a, b, 7);
  EXPECT_EQ(again.interval.lo, c.interval.lo);
  EXPECT_EQ(again.interval.hi, c.interval.hi);
  EXPECT_EQ(c.test.n, 5);
  EXPECT_TRUE(std::isnan(compare_paired({1, 2}, {2, 1}, 7).interval.lo));
}

// 400 simulated runs of 40 cases with errors N(0.5, 1): the true RMSE is sqrt(1.25);
// the 95 % percentile interval should hold it in about 95 % of runs (the percentile
// bootstrap runs a little under at this size), and the bias interval hold 0.5.
TEST(Statistics, BootstrapIntervalsCoverTheTrueValueAtAboutTheStatedRate) {
  Rng rng(20261130);
  const int runs = 400, n = 40;
  int rmse_hits = 0, bias_hits = 0;
  for (int r = 0; r < runs; ++r) {
    std::vector<double> est(n), truth(n);
    for (int i = 0; i < n; ++i) {
      truth[static_cast<std::size_t>(i)] = rng.uniform(500, 2000);
      est[static_cast<std::size_t>(i)] = truth[static_cast<std::size_t>(i)] + rng.normal(0.5, 1.0);
    }
    const ScoreIntervals s = bootstrap_score_intervals(est, truth, derive_seed(99, static_cast<std::uint64_t>(r)), 1000);
    rmse_hits += s.rmse.lo <= std::sqrt(1.25) && std::sqrt(1.25) <= s.rmse.hi;
    bias_hits += s.bias.lo <= 0.5 && 0.5 <= s.bias.hi;
  }
  const double rmse_rate = static_cast<double>(rmse_hits) / runs, bias_rate = static_cast<double>(bias_hits) / runs;
  RecordProperty("rmse_coverage", std::to_string(rmse_rate));
  RecordProperty("bias_coverage", std::to_string(bias_rate));
  EXPECT_GT(rmse_rate, 0.88) << rmse_rate;
  EXPECT_LT(rmse_rate, 0.99) << rmse_rate;
  EXPECT_GT(bias_rate, 0.90) << bias_rate;
  EXPECT_LT(bias_rate, 0.99) << bias_rate;
  std::printf("coverage of the 95 %% intervals over %d runs of %d cases: RMSE %.3f, bias %.3f\n", runs, n, rmse_rate,
              bias_rate);
}

// Lag correlation by hand: a row that alternates gives r = -1 at lag 1 and +1 at lag
// 2; NaN gaps drop their pairs; maps pool.
TEST(Statistics, LagCorrelationByHand) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  LagCorrelation c({1, 2, 3});
  c.add({1, -1, 1, -1, 1, -1}, 6, 1);
  c.add({2, -2, 2, nan, 2, -2, 2, -2}, 4, 2);
  const std::vector<double> r = c.correlations();
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NEAR(r[0], -1, 1e-12);
  EXPECT_NEAR(r[1], 1, 1e-12);
  EXPECT_NEAR(r[2], -1, 1e-12);
  LagCorrelation few({1});
  few.add({1, 2, nan, 4}, 4, 1);  // one pair
  EXPECT_TRUE(std::isnan(few.correlations()[0]));
  EXPECT_THROW(few.add({1, 2, 3}, 2, 2), std::invalid_argument);
  EXPECT_THROW(LagCorrelation({0}), std::invalid_argument);
}

}  // namespace
}  // namespace grapebench
