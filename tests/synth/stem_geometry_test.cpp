#include "synth/stem_geometry.h"

#include "synth/config.h"
#include "synth/rng.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

TEST(StemGeometry, SegmentDistances) {
  EXPECT_NEAR(point_segment_distance(Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)), 1.0, 1e-15);
  EXPECT_NEAR(point_segment_distance(Vec3(3, 0, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)), 1.0, 1e-15);
  EXPECT_NEAR(segment_segment_distance(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 2), Vec3(0.5, 1, 2)), 2.0, 1e-15);
  EXPECT_NEAR(segment_segment_distance(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)), 1.0, 1e-15);
}

TEST(StemGeometry, ExitDistanceThroughSideAndCap) {
  const Stem s{Vec3(0, 0, 0), Vec3(0, 0, 1), 0.5};
  EXPECT_NEAR(exit_distance(s, Vec3(0, 0, 0.5), Vec3(1, 0, 0)), 0.5, 1e-15);
  EXPECT_NEAR(exit_distance(s, Vec3(0, 0, 0.5), Vec3(0, 0, 1)), 0.5, 1e-15);
  EXPECT_NEAR(exit_distance(s, Vec3(0, 0, 0.9), Vec3(std::sqrt(0.5), 0, std::sqrt(0.5))), 0.1 * std::sqrt(2), 1e-15);
}

// Perpendicular child from the axis of a long parent: the overlap is
// int_{-r}^{r} 2 sqrt(r^2 - v^2) sqrt(R^2 - v^2) dv; with v = r sin(t) the integrand
// is smooth and periodic, so a fine trapezoid rule is a reference to 1e-14.
TEST(StemGeometry, PerpendicularJunctionMatchesOneDimensionalIntegral) {
  const double R = 1.0, r = 0.5;
  const Stem parent{Vec3(0, 0, -5), Vec3(0, 0, 5), R};
  const Stem child{Vec3(0, 0, 0), Vec3(3, 0, 0), r};
  double ref = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const double t = -M_PI / 2 + M_PI * (k + 0.5) / n;
    const double v = r * std::sin(t);
    ref += 2 * r * std::cos(t) * std::sqrt(R * R - v * v) * r * std::cos(t) * (M_PI / n);
  }
  EXPECT_NEAR(junction_overlap_volume(child, parent), ref, 1e-10 * ref);
}

// Oblique child leaving through the parent's end cap (the rachis in the peduncle's
// stub): the fixed quadrature against Monte Carlo.
TEST(StemGeometry, ObliqueJunctionThroughCapMatchesMonteCarlo) {
  const Stem parent{Vec3(0, 0, -0.3), Vec3(0.2, 0, 2), 0.5};
  const Vec3 start = parent.start + 0.15 * (parent.end - parent.start).normalized();
  const Stem child{start, start + Vec3(0.3, 0.1, -1.5), 0.3};
  const double v = junction_overlap_volume(child, parent);
  Rng rng(3);
  long hits = 0;
  const long n = 4'000'000;
  const Vec3 lo(-1, -1, -1.5), hi(1, 1, 1);
  for (long k = 0; k < n; ++k) {
    const Vec3 x(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), rng.uniform(lo.z(), hi.z()));
    hits += inside_stem(child, x) && inside_stem(parent, x);
  }
  const double box = (hi - lo).prod(), p = static_cast<double>(hits) / n;
  EXPECT_NEAR(v, box * p, 3 * box * std::sqrt(p * (1 - p) / n));
}

TEST(StemGeometry, PedicelInBerryClosedFormMatchesMonteCarlo) {
  const Berry b{Vec3(0.1, 0.2, 0.3), 1.0, {}, -1};
  const Vec3 d = Vec3(1, 2, -1).normalized();
  const Stem ped{b.centre - 1.6 * d, b.centre - 0.5 * d, 0.3, Part::Pedicel};
  const double v = pedicel_in_berry_volume(ped, b);
  Rng rng(5);
  long hits = 0;
  const long n = 4'000'000;
  const Vec3 lo = b.centre - Vec3::Constant(1.1), hi = b.centre + Vec3::Constant(1.1);
  for (long k = 0; k < n; ++k) {
    const Vec3 x(rng.uniform(lo.x(), hi.x()), rng.uniform(lo.y(), hi.y()), rng.uniform(lo.z(), hi.z()));
    hits += inside_stem(ped, x) && (x - b.centre).norm() <= b.radius;
  }
  const double box = (hi - lo).prod(), p = static_cast<double>(hits) / n;
  EXPECT_NEAR(v, box * p, 3 * box * std::sqrt(p * (1 - p) / n));
}

TEST(StemGeometry, PedicelOffAxisIsRejected) {
  const Berry b{Vec3(0, 0, 0), 1.0, {}, -1};
  const Stem ped{Vec3(0.1, 0, -2), Vec3(0.1, 0, -0.5), 0.2, Part::Pedicel};
  EXPECT_THROW(pedicel_in_berry_volume(ped, b), InputError);
}

}  // namespace
}  // namespace grapebench
