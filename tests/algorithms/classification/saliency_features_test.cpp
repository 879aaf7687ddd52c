// Seed 004's saliency features on exact samplings: a line is curve-like, a plane
// surface-like, a ball point-like (Dey et al. 2012 Eq. 2), at any offset and density.
#include <gtest/gtest.h>

#include <cmath>

#include "algorithms/classification/saliency_features.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// Which of point-ness, curve-ness, surface-ness dominates at the point nearest `at`.
int dominant(const PointCloud& cloud, const SaliencyParams& p, Eigen::Index at, Eigen::Vector3d* value = nullptr) {
  const SaliencyFeatures f = saliency_features(cloud, {}, p);
  const Eigen::Vector3d s = f.features.block<1, 3>(at, 0).transpose();
  if (value) *value = s;
  Eigen::Index best = 0;
  s.maxCoeff(&best);
  return static_cast<int>(best);
}

SaliencyParams one_scale(double r) {
  SaliencyParams p;
  p.radius = r, p.scales = 1, p.colour = false;
  return p;
}

const Vec3 kFar(1000.0, -2000.0, 50.0);  // far from the origin: the sums stay exact

TEST(SaliencyFeatures, LineIsCurveLike) {
  PointCloud c(201, 3);
  for (int i = 0; i < 201; ++i) c.row(i) = (kFar + Vec3(0.001 * (i - 100), 0, 0)).transpose();
  Eigen::Vector3d s;
  EXPECT_EQ(dominant(c, one_scale(0.0495), 100, &s), 1);  // not 0.05: points exactly on the sphere
  // Evenly spaced points, n = 99 of spacing h: variance (n^2 - 1) h^2 / 12.
  EXPECT_NEAR(s[1], (99.0 * 99 - 1) * 1e-6 / 12, 1e-9);
  EXPECT_NEAR(s[0], 0, 1e-12);
}

TEST(SaliencyFeatures, PlaneIsSurfaceLike) {
  // A 120 mm square: the centre's 50 mm disc lies inside it (a larger plane only costs
  // every other point's neighbourhood: 25 s under ASan at 200 mm).
  PointCloud c(61 * 61, 3);
  for (int i = 0; i < 61; ++i)
    for (int j = 0; j < 61; ++j) c.row(i * 61 + j) = (kFar + Vec3(0.002 * (i - 30), 0.002 * (j - 30), 0)).transpose();
  Eigen::Vector3d s;
  EXPECT_EQ(dominant(c, one_scale(0.05), 30 * 61 + 30, &s), 2);
  EXPECT_NEAR(s[0], 0, 1e-12);              // no spread normal to the plane
  EXPECT_LT(s[1], 0.05 * s[2]);             // a disc: lambda0 = lambda1
}

TEST(SaliencyFeatures, BallIsPointLike) {
  // A solid ball of 60 mm at 20000 points per (100 mm)^3 ball: the centre's 50 mm
  // neighbourhood (about 2500 points) lies inside it.
  Rng rng(7);
  const int n = 4320;  // 20000 * 0.6^3
  PointCloud c(n, 3);
  for (int i = 0; i < n; ++i) {
    Vec3 v;
    do v = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    while (v.norm() > 1);
    c.row(i) = (kFar + 0.06 * v).transpose();
  }
  c.row(0) = kFar.transpose();
  Eigen::Vector3d s;
  EXPECT_EQ(dominant(c, one_scale(0.05), 0, &s), 0);
  EXPECT_NEAR(s[0], 0.05 * 0.05 / 5, 0.1 * 0.05 * 0.05 / 5);  // a solid ball: variance r^2 / 5 per axis
}

TEST(SaliencyFeatures, ScalesInThePapersOrderThenColour) {
  SaliencyParams p;
  p.radius = 0.04, p.scales = 3;
  const std::vector<double> r = saliency_radii(p);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_DOUBLE_EQ(r[0], 0.04);
  EXPECT_DOUBLE_EQ(r[1], 0.02);
  EXPECT_DOUBLE_EQ(r[2], 0.08);
  PointCloud c(3, 3);
  c << 0, 0, 0, 0.01, 0, 0, 0.03, 0, 0;
  const SaliencyFeatures f = saliency_features(c, {{255, 0, 0}, {0, 255, 0}, {0, 0, 51}}, p);
  ASSERT_EQ(f.features.cols(), 12);
  EXPECT_EQ(f.neighbours[0 * 3 + 0], 3);  // point 0 at 4 cm sees all three
  EXPECT_EQ(f.neighbours[0 * 3 + 1], 2);  // at 2 cm, itself and the one at 1 cm
  EXPECT_DOUBLE_EQ(f.features(2, 11), 0.2);
  EXPECT_THROW(saliency_features(c, {{0, 0, 0}}, p), InputError);
}

TEST(SaliencyFeatures, ScalingStandardisesColumns) {
  Eigen::MatrixXd x(4, 2);
  x << 1, 5, 2, 5, 3, 5, 4, 5;
  const FeatureScaling s = fit_scaling(x);
  const Eigen::MatrixXd y = s.apply(x);
  EXPECT_NEAR(y.col(0).mean(), 0, 1e-12);
  EXPECT_NEAR(y.col(0).squaredNorm() / 4, 1, 1e-12);
  EXPECT_NEAR(y.col(1).norm(), 0, 1e-12);  // constant: centred, not divided by 0
}

}  // namespace
}  // namespace grapebench
