#include "bench/stereo_tables.h"

#include <gtest/gtest.h>

namespace grapebench {
namespace {

// Reference values: Wilson's formula evaluated independently (Python, z = 1.96).
TEST(StereoTables, WilsonInterval) {
  auto [lo, hi] = wilson_interval(87, 100);
  EXPECT_NEAR(lo, 0.7901947810519012, 1e-12);
  EXPECT_NEAR(hi, 0.9224290614158575, 1e-12);
  std::tie(lo, hi) = wilson_interval(0, 10);
  EXPECT_NEAR(lo, 0, 1e-15);
  EXPECT_NEAR(hi, 0.2775401687666165, 1e-12);
  std::tie(lo, hi) = wilson_interval(10, 10);
  EXPECT_NEAR(lo, 0.7224598312333834, 1e-12);
  EXPECT_NEAR(hi, 1, 1e-15);
  EXPECT_TRUE(std::isnan(wilson_interval(0, 0).first));
}

EstimateRow row(const char* quantity, const char* station, double estimate, double truth, bool ok = true) {
  EstimateRow r;
  r.estimator = "luo";
  r.quantity = quantity;
  r.roi = station;
  r.estimate = estimate;
  r.truth = truth;
  r.ok = ok;
  return r;
}

// Success per condition, berries and |e_z|, |e_x| per 100 mm bin, failures left out
// of the errors but counted in the success rate.
TEST(StereoTables, SuccessByConditionAndErrorsByDepth) {
  CaseResult a, b;
  a.condition = 0, b.condition = 1;
  a.rows = {row("cut_success", "station_0350mm", 1, 1), row("cut_z", "station_0350mm", 0.352, 0.350),
            row("cut_x", "station_0350mm", 0.011, 0.010), row("berries_found", "station_0350mm", 20, 25),
            row("cut_success", "station_0440mm", 0, 1), row("cut_z", "station_0440mm", 0, 0, false),
            row("berries_found", "station_0440mm", 10, 20), row("cut_success", "station_0800mm", 1, 1),
            row("cut_z", "station_0800mm", 0.806, 0.800), row("cut_x", "station_0800mm", -0.003, 0.001)};
  b.rows = {row("cut_success", "station_0800mm", 0, 1)};
  const StereoTables t = stereo_tables({a, b}, {"light=front", "light=overcast"});
  ASSERT_EQ(t.success.size(), 2u);
  EXPECT_EQ(t.success[0].condition, "light=front");
  EXPECT_EQ(t.success[0].pairs, 3);
  EXPECT_EQ(t.success[0].successes, 2);
  EXPECT_NEAR(t.success[0].rate, 2.0 / 3, 1e-12);
  EXPECT_EQ(t.success[1].pairs, 1);
  EXPECT_EQ(t.success[1].successes, 0);
  ASSERT_EQ(t.depth.size(), 2u);  // 350 and 440 mm share the 400 mm bin
  EXPECT_EQ(t.depth[0].depth_mm, 400);
  EXPECT_EQ(t.depth[0].visible, 45);
  EXPECT_EQ(t.depth[0].found, 30);
  EXPECT_EQ(t.depth[0].answered, 1);
  EXPECT_NEAR(t.depth[0].ez_mm, 2, 1e-9);
  EXPECT_NEAR(t.depth[0].ex_mm, 1, 1e-9);
  EXPECT_EQ(t.depth[1].depth_mm, 800);
  EXPECT_NEAR(t.depth[1].ez_mm, 6, 1e-9);
  EXPECT_NEAR(t.depth[1].ex_mm, 4, 1e-9);
}

}  // namespace
}  // namespace grapebench
