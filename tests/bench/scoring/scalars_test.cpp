// Scalar scores on a hand-computed case: estimates 2, 4, 7 against truths 1, 3, 5,
// and a fourth case that failed.
#include "bench/scoring/scalars.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(ScalarScores, HandComputedCase) {
  const Score s = score({2, 4, 7}, {1, 3, 5}, 4, {1, 2, 3, 4});
  EXPECT_EQ(s.cases, 4);
  EXPECT_EQ(s.succeeded, 3);
  EXPECT_DOUBLE_EQ(s.success_rate, 0.75);
  // Errors 1, 1, 2.
  EXPECT_DOUBLE_EQ(s.bias, 4.0 / 3);
  EXPECT_DOUBLE_EQ(s.mae, 4.0 / 3);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(2.0));
  EXPECT_NEAR(s.mape, 100 * (1.0 + 1.0 / 3 + 2.0 / 5) / 3, 1e-12);
  // Sxx = 8, Sxy = 10, Syy = 114/9: slope 1.25, intercept 13/3 - 3.75.
  EXPECT_DOUBLE_EQ(s.slope, 1.25);
  EXPECT_NEAR(s.intercept, 13.0 / 3 - 3.75, 1e-12);
  EXPECT_NEAR(s.r2, 100.0 / (8.0 * 114.0 / 9.0), 1e-12);
  // About y = x: 1 - SS_res / SS_tot = 1 - 6 / 8.
  EXPECT_DOUBLE_EQ(s.r2_identity, 0.25);
  EXPECT_DOUBLE_EQ(s.time_median, 2.5);
}

TEST(ScalarScores, NoSuccessfulCaseGivesNaNNotANumber) {
  const Score s = score({}, {}, 2, {});
  EXPECT_EQ(s.succeeded, 0);
  EXPECT_DOUBLE_EQ(s.success_rate, 0);
  EXPECT_TRUE(std::isnan(s.rmse));
  EXPECT_TRUE(std::isnan(s.r2));
}

}  // namespace
}  // namespace grapebench
