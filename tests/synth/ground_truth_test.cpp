// Exact ground truth of simple bunches with closed-form answers.
#include "synth/ground_truth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "synth/rng.h"

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

// The hull of a large cloud (filtered before CGAL) is the hull of its own vertices
// (too few to be filtered): the same vertex set and the same exact volume.
TEST(ConvexHull, DroppingInnerPointsFirstChangesNothing) {
  Rng rng(5);
  std::vector<std::vector<Vec3>> clouds(3);
  for (int i = 0; i < 20000; ++i) {  // a ball's surface and inside
    const Vec3 u = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    clouds[0].push_back(u * (i % 40 ? 0.05 * rng.uniform() : 0.05));
  }
  for (int i = 0; i < 30000; ++i)  // a box's inside, faces and corners: coplanar points galore
    clouds[1].push_back(Vec3(std::round(rng.uniform() * 4) / 4, std::round(rng.uniform() * 4) / 4, rng.uniform() * 0.1));
  for (int i = 0; i < 5000; ++i)  // a thin needle along a diagonal (a grid of one-cell slabs)
    clouds[2].push_back(Vec3(1, 1, 1) * rng.uniform() + 1e-4 * Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
  for (const auto& c : clouds) {
    const HullMesh all = convex_hull(c);
    ASSERT_LT(all.vertices.size(), 1000u);
    const HullMesh own = convex_hull(all.vertices);
    EXPECT_EQ(all.volume, own.volume);
    auto sorted = [](std::vector<Vec3> v) {
      std::sort(v.begin(), v.end(), [](const Vec3& a, const Vec3& b) {
        return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
      });
      return v;
    };
    EXPECT_EQ(sorted(all.vertices), sorted(own.vertices));
  }
}

}  // namespace
}  // namespace grapebench
