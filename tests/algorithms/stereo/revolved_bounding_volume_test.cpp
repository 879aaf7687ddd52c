#include "algorithms/stereo/revolved_bounding_volume.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

// Points on a ring of radius r about the vertical through `origin`, y below it.
std::vector<Vec3> ring(const Vec3& origin, double r, double y, int n) {
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    out.push_back(origin + Vec3(r * std::cos(a), y, r * std::sin(a)));
  }
  return out;
}

// A ring below the cutting point: the section is the triangle (0, 0), (R, H), (0, H),
// revolved a cone of volume pi R^2 H / 3.
TEST(RevolvedBoundingVolume, ARingBelowTheOriginIsACone) {
  const Vec3 origin(0.03, -0.02, 0.7);
  const double R = 0.06, H = 0.15;
  const RevolvedBoundingVolume v = revolved_bounding_volume(origin, ring(origin, R, H, 12));
  EXPECT_NEAR(v.volume, M_PI * R * R * H / 3, 1e-12);
  EXPECT_NEAR(v.height, H, 1e-12);
  EXPECT_NEAR(v.max_diameter, 2 * R, 1e-12);
  EXPECT_EQ(v.section.size(), 3u);
}

// Two rings at y = a and y = b: the section (0, 0), (R, a), (R, b), (0, b) revolves
// into a cone of height a on a cylinder of height b - a.
TEST(RevolvedBoundingVolume, TwoRingsAreAConeOnACylinder) {
  const Vec3 origin = Vec3::Zero();
  const double R = 0.05, a = 0.02, b = 0.17;
  std::vector<Vec3> pts = ring(origin, R, a, 8);
  for (const Vec3& p : ring(origin, R, b, 5)) pts.push_back(p);
  const RevolvedBoundingVolume v = revolved_bounding_volume(origin, pts);
  EXPECT_NEAR(v.volume, M_PI * R * R * a / 3 + M_PI * R * R * (b - a), 1e-12);
  EXPECT_NEAR(v.height, b, 1e-12);
  EXPECT_NEAR(v.max_diameter, 2 * R, 1e-12);
}

// Only the distance from the axis counts (Eq. 9): one point per height gives the same
// section as a full ring, and inner points change nothing.
TEST(RevolvedBoundingVolume, OnlyTheDistanceFromTheAxisCounts) {
  const Vec3 origin(0.1, 0.2, 0.9);
  const double R = 0.04, H = 0.1;
  const RevolvedBoundingVolume one = revolved_bounding_volume(origin, {origin + Vec3(0, H, R)});
  std::vector<Vec3> more = ring(origin, R, H, 7);
  more.push_back(origin + Vec3(0.01, 0.5 * H, 0));  // inside the cone
  const RevolvedBoundingVolume many = revolved_bounding_volume(origin, more);
  EXPECT_NEAR(one.volume, many.volume, 1e-15);
  EXPECT_NEAR(one.volume, M_PI * R * R * H / 3, 1e-12);
}

TEST(RevolvedBoundingVolume, NoPointsIsEmpty) {
  const RevolvedBoundingVolume v = revolved_bounding_volume(Vec3::Zero(), {});
  EXPECT_EQ(v.volume, 0);
  EXPECT_EQ(v.height, 0);
  EXPECT_EQ(v.max_diameter, 0);
}

}  // namespace
}  // namespace grapebench
