// Exact ground truth of simple bunches with closed-form answers.
#include "synth/ground_truth.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(GroundTruth, SectionPerimetersOfOneBerryAreItsGreatCircle) {
  Bunch b;
  b.berries.push_back({Vec3(0.01, -0.02, 0.5), 0.009, {}, -1});
  const GroundTruth g = compute_ground_truth(b, 1.1);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.section_perimeter(k) / (2 * M_PI * 0.009), 1, 1e-6) << k;
}

TEST(GroundTruth, SectionPerimeterOfTwoTouchingBerriesIsTheirStadium) {
  // Two equal balls on the x axis: the section normal to the middle or minor axis
  // through the centre is two discs, whose convex outline is a stadium.
  Bunch b;
  const double r = 0.01, gap = 0.03;
  b.berries.push_back({Vec3(0, 0, 0), r, {}, -1});
  b.berries.push_back({Vec3(gap, 0, 0), r, {}, -1});
  const GroundTruth g = compute_ground_truth(b, 1.1);
  const double stadium = 2 * M_PI * r + 2 * gap;
  EXPECT_NEAR(g.section_perimeter(1) / stadium, 1, 1e-6);
  EXPECT_NEAR(g.section_perimeter(2) / stadium, 1, 1e-6);
  // Normal to the major axis, through the middle of the gap: no solid there.
  EXPECT_EQ(g.section_perimeter(0), 0);
}

}  // namespace
}  // namespace grapebench
