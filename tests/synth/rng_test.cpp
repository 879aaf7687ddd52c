// The stateless draws behind per-pixel noise: the tabulated normal agrees with the
// formula, both are deterministic, and their moments are those of N(0, 1).
#include "synth/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(Rng, TabulatedNormalMatchesTheInverseCdfFormula) {
  const NormalTable table;
  double worst = 0;
  for (int i = 1; i < 2000000; ++i) {
    const double p = i / 2000000.0;
    worst = std::max(worst, std::abs(table(p) - inverse_normal_cdf(p)));
    if (i > 10) i += 6;  // a dense sweep, cheap enough for the default build
  }
  EXPECT_LT(worst, 2e-6) << "worst interpolation error";
}

TEST(Rng, HashedNormalsAreDeterministicWithUnitMoments) {
  const int n = 400000;
  double s1 = 0, s2 = 0, t1 = 0, t2 = 0;
  for (int i = 0; i < n; ++i) {
    const double a = hashed_normal(42, i), b = hashed_normal_tabulated(42, i);
    EXPECT_EQ(a, hashed_normal(42, i));
    s1 += a;
    s2 += a * a;
    t1 += b;
    t2 += b * b;
  }
  // Mean within 5 standard errors of 0, variance within 1 %.
  EXPECT_NEAR(s1 / n, 0.0, 5 / std::sqrt(n));
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
  EXPECT_NEAR(t1 / n, 0.0, 5 / std::sqrt(n));
  EXPECT_NEAR(t2 / n, 1.0, 0.01);
}

}  // namespace
}  // namespace grapebench
