// Point scores on a hand-computed case: errors (1, 0, 0) and (0, 2, 0), one case
// without an answer, tolerance 1.5 m.
#include "bench/scoring/points.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace grapebench {
namespace {

TEST(PointScores, HandComputedCase) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const PointScore s = score_points({Vec3(1, 0, 0), Vec3(0, 2, 0), Vec3(nan, 0, 0)},
                                    {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, 1.5);
  EXPECT_EQ(s.cases, 3);
  EXPECT_EQ(s.answered, 2);
  EXPECT_EQ(s.within, 1);
  EXPECT_DOUBLE_EQ(s.success_rate, 1.0 / 3);
  EXPECT_DOUBLE_EQ(s.mean_error, 1.5);
  EXPECT_DOUBLE_EQ(s.median_error, 1.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(2.5));
  EXPECT_DOUBLE_EQ(s.max_error, 2);
  EXPECT_DOUBLE_EQ(s.axis_bias[0], 0.5);
  EXPECT_DOUBLE_EQ(s.axis_bias[1], 1);
  EXPECT_DOUBLE_EQ(s.axis_bias[2], 0);
  EXPECT_DOUBLE_EQ(s.axis_rmse[0], std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(s.axis_rmse[1], std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(s.axis_mae[1], 1);
}

TEST(PointScores, SignedBiasAndNoAnswer) {
  const PointScore s = score_points({Vec3(-1, 0, 0), Vec3(-3, 0, 0)}, {Vec3::Zero(), Vec3::Zero()}, 10);
  EXPECT_DOUBLE_EQ(s.axis_bias[0], -2);
  EXPECT_DOUBLE_EQ(s.axis_mae[0], 2);
  EXPECT_DOUBLE_EQ(s.success_rate, 1);
  const PointScore none = score_points({Vec3::Constant(std::nan(""))}, {Vec3::Zero()}, 1);
  EXPECT_EQ(none.answered, 0);
  EXPECT_DOUBLE_EQ(none.success_rate, 0);
  EXPECT_TRUE(std::isnan(none.rmse));
  EXPECT_THROW(score_points({Vec3::Zero()}, {}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace grapebench
