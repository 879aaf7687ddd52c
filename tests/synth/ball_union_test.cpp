#include "synth/ball_union.h"

#include "synth/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

double ball(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }
double cap(double r, double h) { return M_PI * h * h * (3 * r - h) / 3; }

TEST(BallPolyhedron, WholeBallInsideBox) {
  const auto box = make_box(Vec3(0.1, -0.2, 0.05), 2.0);
  EXPECT_NEAR(ball_polyhedron_volume(Vec3::Zero(), 1.3, box), ball(1.3), 1e-12);
  EXPECT_NEAR(polyhedron_volume(box), 64.0, 1e-12);
}

TEST(BallPolyhedron, PlaneCutsOffACapWithCentreInsideOrOutside) {
  auto keep_below = make_box(Vec3::Zero(), 2.0);
  clip(keep_below, {Vec3(0, 0, 1), 0.4}, 0);
  EXPECT_NEAR(ball_polyhedron_volume(Vec3::Zero(), 1.3, keep_below), ball(1.3) - cap(1.3, 0.9), 1e-12);
  auto cap_only = make_box(Vec3::Zero(), 2.0);
  clip(cap_only, {Vec3(0, 0, -1), -0.5}, 0);  // keeps z >= 0.5: the centre is outside
  EXPECT_NEAR(ball_polyhedron_volume(Vec3::Zero(), 1.3, cap_only), cap(1.3, 0.8), 1e-12);
}

TEST(BallPolyhedron, ThinBoxFarFromCentre) {
  // A cube whose lower face z = 0.9 cuts the unit ball: only the cap is inside.
  const auto cube = make_box(Vec3(0, 0, 1.9), 1.0);
  EXPECT_NEAR(ball_polyhedron_volume(Vec3::Zero(), 1.0, cube), cap(1.0, 0.1), 1e-14);
}

TEST(UnionOfBalls, TwoBallsLens) {
  const std::vector<Vec3> c = {Vec3(0, 0, 0), Vec3(1.5, 0.2, 0.1)};
  const std::vector<double> r = {1.0, 0.8};
  const double d = (c[1] - c[0]).norm(), R1 = 1.0, R2 = 0.8;
  const double lens = M_PI * std::pow(R1 + R2 - d, 2) *
                      (d * d + 2 * d * R2 - 3 * R2 * R2 + 2 * d * R1 + 6 * R1 * R2 - 3 * R1 * R1) / (12 * d);
  EXPECT_NEAR(union_of_balls_volume(c, r), ball(R1) + ball(R2) - lens, 1e-12);
}

TEST(UnionOfBalls, DisjointTangentNestedAndCoincident) {
  EXPECT_NEAR(union_of_balls_volume({Vec3(0, 0, 0), Vec3(3, 0, 0)}, {1, 1}), 2 * ball(1), 1e-12);
  EXPECT_NEAR(union_of_balls_volume({Vec3(0, 0, 0), Vec3(2, 0, 0)}, {1, 1}), 2 * ball(1), 1e-12);
  EXPECT_NEAR(union_of_balls_volume({Vec3(0, 0, 0), Vec3(0.2, 0, 0)}, {1, 0.5}), ball(1), 1e-12);
  EXPECT_NEAR(union_of_balls_volume({Vec3(0, 0, 0), Vec3(0, 0, 0)}, {1, 1}), ball(1), 1e-12);
}

TEST(UnionOfBalls, ClusterAgreesWithMonteCarlo) {
  // Twelve mutually overlapping balls: triple and quadruple overlaps included.
  Rng rng(11);
  std::vector<Vec3> c;
  std::vector<double> r;
  for (int i = 0; i < 12; ++i) {
    c.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    r.push_back(rng.uniform(0.4, 0.9));
  }
  const double exact = union_of_balls_volume(c, r);
  const long n = 4'000'000;
  long hits = 0;
  for (long k = 0; k < n; ++k) {
    const Vec3 x(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    for (int i = 0; i < 12; ++i) {
      if ((x - c[i]).squaredNorm() <= r[i] * r[i]) {
        ++hits;
        break;
      }
    }
  }
  const double p = static_cast<double>(hits) / n, mc = 64 * p, se = 64 * std::sqrt(p * (1 - p) / n);
  EXPECT_NEAR(exact, mc, 3 * se) << "exact " << exact << " mc " << mc << " se " << se;
}

}  // namespace
}  // namespace grapebench
